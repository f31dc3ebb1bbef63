"""The spool winch (cdpr.models.winch spool functions) against RepRapFirmware's Hangprinter formula.

RepRapFirmware's HangprinterKinematics (Duet3D/RepRapFirmware, src/Movement/Kinematics/
HangprinterKinematics.cpp) turns a line-length change Δ [mm] (anchor-mover relaxed length minus its
value at the origin) into motor steps with

    spr = U J μ H / (2 π L)            (steps per mm at unit radius; J full steps per motor turn,
                                         μ microsteps)
    k2  = -U O Q,   k0 = 2 spr / k2
    steps = k0 (sqrt(R² + k2 Δ) - R)                       (CartesianToMotorSteps)
    Δ = ((steps / k0 + R)² - R²) / k2                      (MotorPosToLinePos)

``rrf_steps`` and ``rrf_line`` below are that formula, written here from the firmware's algebra
(not from cdpr; O, lines per spool, is N in the code), in 50-digit decimals so that the reference carries no rounding of its own; a motor
angle in degrees is steps / (J μ) * 360.
"""

import decimal
import math

import numpy as np
import pytest

from cdpr.models import winch
from cdpr.robot import SpoolParams

J, MU = 25, 256  # the firmware's default full steps per motor turn; any microstepping


D = decimal.Context(prec=50)  # the firmware's form cancels digits near Δ = 0: evaluate it exactly
PI = D.create_decimal("3.14159265358979323846264338327950288419716939937510")


def _k(R, Q, U, N, L, H):
    spr = D.divide(D.create_decimal(U * J * MU * H), 2 * PI * L)
    k2 = D.create_decimal(-U * N) * D.create_decimal(repr(Q))
    return spr, k2, D.divide(2 * spr, k2)


def rrf_steps(delta_mm, R, Q, U, N, L, H):
    _, k2, k0 = _k(R, Q, U, N, L, H)
    R = D.create_decimal(repr(R))
    return float(k0 * ((R * R + k2 * D.create_decimal(repr(float(delta_mm)))).sqrt(D) - R))


def rrf_line(steps, R, Q, U, N, L, H):
    _, k2, k0 = _k(R, Q, U, N, L, H)
    R = D.create_decimal(repr(R))
    return float(((D.create_decimal(repr(float(steps))) / k0 + R) ** 2 - R * R) / k2)


#: (R [mm], Q [mm], U, O, L, H): the HP4's (its author's buildup, D's U = 4), RepRapFirmware's default
#: buildup, two lines per spool, and a strong buildup.
MACHINES = [
    (75.0, 0.06875, 2, 1, 20, 255),
    (75.657, 0.06875, 4, 1, 20, 255),
    (75.0, 0.007, 2, 1, 20, 255),
    (60.0, 0.05, 1, 2, 12, 100),
    (40.0, 0.3, 3, 1, 20, 255),
]
#: Line-length changes Δ [mm], wound in and paid out.
DELTAS = [-1500.0, -400.0, -25.0, -0.5, 0.0, 0.5, 25.0, 400.0, 1500.0]


def spool(R, Q, U, N, L, H):
    return SpoolParams(r0=R / 1000, Q=Q / 1000, U=U, lines_per_spool=N, motor_teeth=L, spool_teeth=H)


@pytest.mark.parametrize("machine", MACHINES)
def test_motor_angle_equals_reprapfirmware_on_a_table(machine):
    p = spool(*machine)
    L0_ref = 1.7  # any reference rest length [m]
    delta = np.array(DELTAS)
    got = winch.spool_motor_angle(p, L0_ref + delta / 1000, L0_ref)
    want = np.array([rrf_steps(d, *machine) / (J * MU) * 360.0 for d in delta])
    assert got == pytest.approx(want, rel=1e-12, abs=1e-9)
    # and back: the rest length of those motor angles is RepRapFirmware's line position
    back = winch.spool_rest_length(p, want, L0_ref)
    line = np.array([rrf_line(s * J * MU / 360.0, *machine) for s in want])
    assert (back - L0_ref) * 1000 == pytest.approx(line, rel=1e-10, abs=1e-9)
    assert (back - L0_ref) * 1000 == pytest.approx(delta, rel=1e-10, abs=1e-9)


def test_hand_derived_values():
    """Derived by hand, without the firmware's formula.

    (a) No buildup: R = 75 mm, U = 2, L = 20, H = 255, Δ = 100 mm. The spool releases U Δ = 200 mm,
        turning 200 / 75 rad; the motor turns 255 / 20 times that: 34 rad = 34 * 180 / π deg
        = 1948.0565 deg.
    (b) Buildup: R = 75 mm, O = 1, Q = 0.5 mm, U = 1, gears 1:1, s = 100 mm. r² = 75² - 0.5 * 100
        = 5575 mm², so the spool turns 2 (75 - sqrt(5575)) / 0.5 = 4 (75 - 74.66592) = 1.336309 rad
        = 76.5649 deg; the radius is then sqrt(5575) = 74.66592 mm.
    """
    a = SpoolParams(r0=0.075, Q=0.0, U=2, lines_per_spool=1, motor_teeth=20, spool_teeth=255)
    assert winch.spool_motor_angle(a, 1.1, 1.0) == pytest.approx(1948.0565, abs=5e-4)
    b = SpoolParams(r0=0.075, Q=0.0005, U=1, lines_per_spool=1, motor_teeth=1, spool_teeth=1)
    assert winch.spool_motor_angle(b, 0.1, 0.0) == pytest.approx(76.5649, abs=5e-4)
    phi = math.radians(76.5649)
    # ds/dphi is the spool's radius there: finite difference of released_line
    h = 1e-6
    r = (winch.released_line(phi + h, 0.075, 0.0005) - winch.released_line(phi - h, 0.075, 0.0005)) / (2 * h)
    assert r == pytest.approx(math.sqrt(5575) / 1000, rel=1e-6)


def test_round_trip_vectorised_and_exact():
    rng = np.random.default_rng(7)
    p = spool(75.0, 0.06875, 2, 1, 20, 255)
    deg = rng.uniform(-60000, 60000, size=(50, 7))
    L0 = winch.spool_rest_length(p, deg, 2.0)
    assert L0.shape == (50, 7)
    assert winch.spool_motor_angle(p, L0, 2.0) == pytest.approx(deg, rel=1e-12, abs=1e-8)
    L = rng.uniform(0.5, 4.0, size=(3, 4, 5))
    assert winch.spool_rest_length(p, winch.spool_motor_angle(p, L, 2.0), 2.0) == pytest.approx(L, rel=1e-13)


def test_buildup_radius_law_and_zero_limit():
    """r² = r0² - O Q s along the whole spool (the wound-area model), and Q -> 0 is the plain
    spool s = r0 phi, continuously."""
    phi = np.linspace(-30, 30, 61)
    r0, Q, N = 0.075, 0.0002, 2  # N: lines per spool (the firmware's O)
    s = winch.released_line(phi, r0, Q, N)
    r = r0 - 0.5 * N * Q * phi  # the radius the model says, checked against the area law
    assert r**2 == pytest.approx(r0**2 - N * Q * s, rel=1e-12)
    for q in (1e-6, 1e-9, 0.0):
        assert winch.released_line(phi, r0, q) == pytest.approx(r0 * phi, rel=q * 300 + 1e-15, abs=1e-15)
        assert winch.spool_angle_of_line(r0 * phi, r0, q) == pytest.approx(phi, rel=q * 300 + 1e-13)


def test_an_empty_spool_is_nan_not_a_number():
    r0, Q = 0.075, 0.0005  # the spool empties at s = r0² / Q = 11.25 m, phi = 2 r0 / Q = 300 rad
    assert np.isnan(winch.released_line(300.0, r0, Q))
    assert np.isfinite(winch.released_line(299.0, r0, Q))
    assert np.isnan(winch.spool_angle_of_line(11.25, r0, Q))
    assert np.isfinite(winch.spool_angle_of_line(11.2, r0, Q))


def test_gears_and_degrees():
    assert winch.spool_angle(360.0, 20, 255) == pytest.approx(2 * math.pi * 20 / 255)
    assert winch.motor_degrees(winch.spool_angle([1.0, -7.5], 20, 255), 20, 255) == pytest.approx([1.0, -7.5])
