"""config/robots/cube50.yaml (issue 38): CDPR4's point mass scaled ten times, heavy 4 mm cables.
It loads with the values the issue gives, and its centre pose solves in physical mode with and
without sag: both ok, the sag visible (centimetres), the platform lower with heavy cables than with
massless ones under the same commanded rest lengths, and the two engines agreeing."""

from pathlib import Path

import numpy as np
import pytest

from cdpr import solve as door
from cdpr.models.inverse import L_TS
from cdpr.robot import load_robot, with_values

ROBOT = Path(__file__).resolve().parents[1] / "config" / "robots" / "cube50.yaml"
CDPR4 = ROBOT.with_name("cdpr4.yaml")
CENTRE = np.array([[0.0, 0.0, 25.0]])


def test_cube50_is_cdpr4_scaled_ten_times():
    r, r4 = load_robot(ROBOT), load_robot(CDPR4)
    np.testing.assert_allclose(r.A, 10 * r4.A)
    assert r.point_mass and r.suspended_point_mass and r.heavy
    a, a4 = r.arrays, r4.arrays
    for key in ("h", "r_p", "d", "ES", "T_a", "kind"):
        np.testing.assert_array_equal(getattr(a, key), getattr(a4, key))
    np.testing.assert_allclose(a.h, 0.1)
    np.testing.assert_allclose(a.r_p, 0.0665)
    np.testing.assert_allclose(a.d, 4.0)
    np.testing.assert_allclose(a.T_a, 5140.0)
    np.testing.assert_allclose(a.ES, 102.2e9 * np.pi * 0.004**2 / 4)
    np.testing.assert_allclose(a.w, 0.0631 * 9.81)
    assert r.platform.mass == 300.0
    np.testing.assert_allclose([c.material.T_min for c in r.cables], 100.0)


@pytest.mark.parametrize("engine", ["compiled", "numpy"])
def test_cube50_centre_solves_with_and_without_sag(engine):
    heavy = load_robot(ROBOT)
    massless = with_values(heavy, linear_density=0)
    assert not massless.heavy
    L0 = L_TS(massless, CENTRE)  # the standard model's rest lengths (Paty 2021 eq. 2), both robots
    h = door.solve(heavy, CENTRE, redundancy="physical", engine=engine, L0=L0)
    m = door.solve(massless, CENTRE, redundancy="physical", engine=engine, L0=L0)
    assert h["status"][0] == "ok" and m["status"][0] == "ok"
    assert (h["cable_status"] == "catenary").all()
    # by symmetry every cable sags alike, by centimetres over a 43 m span
    assert 0.01 < h["sag"].min() and np.ptp(h["sag"]) < 1e-9 * h["sag"].max()
    # under the same rest lengths the heavy cables let the platform down: the pose error sag adds
    dz = h["P_s"][0, 2] - m["P_s"][0, 2]
    assert dz < -1e-4 and np.abs(h["P_s"][0, :2]).max() < 1e-9  # 0.6 mm at the centre
    # the cables carry their own weight: more tension at the pulley than at the platform
    assert (h["t_D"] > h["t_B"]).all()
    np.testing.assert_allclose(h["t_D"] - h["t_B"], 0.0631 * 9.81 * (50.0 - h["P_s"][0, 2]), rtol=0.05)
