"""Geometric model of a single-layer CDPR winch (Métillon et al. 2022, the "winch seed").

The drum exit point E slides along the segment E1E2 as the drum turns (eq. 12), so the cable
length between E and the pulley entry point A varies with the joint angle q. Substituting into the
length balance gives a quadratic in q (eq. 23). Corrections to the printed equations (see
docs/models.md):

* eq. (19): the uncoiled length decreases when q grows (eq. 17), so |e - a| = X - k_w q with
  X = l_u0 + k_w q0 - l_pm (the printed "+ k_w (q - q0)" has the wrong sign);
* eq. (27): a = l_E1E2^2 / q_max^2 - k_w^2 = -r_w^2 (the printed form drops the squares);
* eq. (29)-(30): the roots are (-b +/- sqrt(Delta)) / (2a), not / (2c); the physical root is the
  one through (l_pm0, q0): q1 = (-b + sqrt(Delta)) / (2a) with a < 0.
* eq. (5): the tangent from A to the drum circle is taken in the plane of the circle, so xi uses
  the distance from D1 to A projected on that plane (equal to |D1A| when A lies in it).

Equation numbers below are those of Métillon 2022 ("eq. (N)" alone means that paper in this
module). Lengths are in m, angles in rad; the functions of one winch take its ``WinchParams`` p.

References
----------
Métillon, M., Charron, C., Subrin, K., Caro, S. (2022). Geometrical modelling of a cable-driven
parallel robot winch. 25e Congrès Français de Mécanique, hal-03758222.
"""

from __future__ import annotations

import math

import numpy as np

from cdpr.errors import CdprError
from cdpr.robot import WinchParams


# ---- winch geometry (eq. 1-13, 18) ---------------------------------------------------------
def coiling_radius(r_d, r_g, r_c):
    """Coiling radius r_w = r_d - r_g + r_c / 2 (Métillon 2022 eq. 7) [m].

    Parameters
    ----------
    r_d : float [m]
        Drum radius.
    r_g : float [m]
        Groove radius.
    r_c : float [m]
        Cable radius.

    Returns
    -------
    r_w : float [m]
        Radius at which the cable axis coils on the drum.
    """
    return r_d - r_g + r_c / 2.0


def coiling_coefficient(r_w, mu):
    """k_w = sqrt(r_w^2 + (mu / 2 pi)^2) (Métillon 2022 eq. 18) [m/rad]; mu is the drum pitch [m].

    Parameters
    ----------
    r_w : float [m]
        Coiling radius (``coiling_radius``).
    mu : float [m]
        Pitch of the drum's helical groove (advance per turn).

    Returns
    -------
    k_w : float [m/rad]
        Cable length coiled per radian of drum rotation (eq. 17: l_u = l_u0 - k_w (q - q0)).
    """
    return math.sqrt(r_w**2 + (mu / (2 * math.pi)) ** 2)


def max_angle(l_E1E2, mu):
    """q_max = 2 pi l_E1E2 / mu (Métillon 2022 eq. 13) [rad].

    Parameters
    ----------
    l_E1E2 : float [m]
        Coiling length, the length of the drum's grooved part along its axis.
    mu : float [m]
        Pitch of the groove.

    Returns
    -------
    q_max : float [rad]
        Drum angle at full coiling (E reaches E2).
    """
    return 2 * math.pi * l_E1E2 / mu


def tangent_angle(D1A_w, r_w):
    """kappa = chi - xi (Métillon 2022 eq. 3-5): direction of D1E1 in the winch frame [rad].

    .. math:: \\chi = \\operatorname{atan2}(z, x), \\quad
        \\xi = \\arccos \\frac{r_w}{\\sqrt{x^2 + z^2}}, \\quad \\kappa = \\chi - \\xi

    with (x, y, z) = D1A_w; xi uses the distance projected on the plane of the drum circle (the
    eq. 5 erratum of the module docstring).

    Parameters
    ----------
    D1A_w : array_like (3,) [m]
        Vector from the drum origin D1 to the pulley entry point A in the winch frame (eq. 6).
    r_w : float [m]
        Coiling radius.

    Returns
    -------
    kappa : float [rad]
        Angle from x_w to D1E1 about the drum axis y_w. Raises ValueError (math domain error) when
        A lies inside the coiling circle (no tangent).
    """
    x, z = D1A_w[0], D1A_w[2]
    chi = math.atan2(z, x)
    xi = math.acos(r_w / math.hypot(x, z))
    return chi - xi


def exit_points(R_wb, d1, a, r_w, l_E1E2):
    """Exit points e1, e2 in the base frame (Métillon 2022 eq. 6-11).

    .. math:: e_1 = d_1 + R_{bw} (r_w \\cos\\kappa, 0, r_w \\sin\\kappa)^T, \\quad
        e_2 = d_1 + R_{bw} (r_w \\cos\\kappa, l_{E_1E_2}, r_w \\sin\\kappa)^T

    with R_bw = R_wb^T and kappa from ``tangent_angle``.

    Parameters
    ----------
    R_wb : array_like (3, 3) [-]
        Rotation from the base to the winch frame (w_R_b of eq. 1; the drum axis is y_w).
    d1 : array_like (3,) [m]
        Drum origin D1 in the base frame.
    a : array_like (3,) [m]
        Pulley entry point A in the base frame.
    r_w : float [m]
        Coiling radius.
    l_E1E2 : float [m]
        Coiling length.

    Returns
    -------
    e1 : ndarray (3,) [m]
        Exit point E1 at q = 0 (empty drum).
    e2 : ndarray (3,) [m]
        Exit point E2 at q = q_max (full drum).
    """
    R_wb = np.asarray(R_wb, dtype=float)
    d1 = np.asarray(d1, dtype=float)
    D1A_w = R_wb @ (np.asarray(a, dtype=float) - d1)
    kappa = tangent_angle(D1A_w, r_w)
    R_bw = R_wb.T
    e1 = d1 + R_bw @ np.array([r_w * math.cos(kappa), 0.0, r_w * math.sin(kappa)])
    e2 = d1 + R_bw @ np.array([r_w * math.cos(kappa), l_E1E2, r_w * math.sin(kappa)])
    return e1, e2


def exit_point(e1, e2, q, q_max):
    """Drum exit point e(q) = e1 + (e2 - e1) q / q_max (Métillon 2022 eq. 12); q may be an array.

    Parameters
    ----------
    e1 : array_like (3,) [m]
        Exit point at q = 0 (``exit_points``).
    e2 : array_like (3,) [m]
        Exit point at q = q_max.
    q : float or array_like (...) [rad]
        Drum angles.
    q_max : float [rad]
        Drum angle at full coiling.

    Returns
    -------
    e : ndarray (..., 3) [m]
        Exit points in the base frame; shape (3,) for a scalar q.
    """
    q = np.asarray(q, dtype=float)[..., None]
    return np.asarray(e1) + (np.asarray(e2) - np.asarray(e1)) * q / q_max


def params_from_geometry(R_wb, d1, a, r_w, mu, l_E1E2, q0, l_u0):
    """WinchParams from the winch geometry and the initial state (q0, l_u0).

    Chains Métillon 2022 eq. (6)-(11) (``exit_points``), (13) (``max_angle``) and (18)
    (``coiling_coefficient``): l_AE1 = |e1 - a| and alpha_E1 the angle between A->E1 and E1->E2.

    Parameters
    ----------
    R_wb : array_like (3, 3) [-]
        Rotation from the base to the winch frame.
    d1 : array_like (3,) [m]
        Drum origin D1 in the base frame.
    a : array_like (3,) [m]
        Pulley entry point A in the base frame.
    r_w : float [m]
        Coiling radius.
    mu : float [m]
        Pitch of the groove.
    l_E1E2 : float [m]
        Coiling length.
    q0 : float [rad]
        Initial drum angle.
    l_u0 : float [m]
        Initial uncoiled length (from E to the platform).

    Returns
    -------
    WinchParams
        k_w [m/rad], l_u0 [m], q0 [rad], q_max [rad], l_AE1 [m], l_E1E2 [m], alpha_E1 [rad].
    """
    e1, e2 = exit_points(R_wb, d1, a, r_w, l_E1E2)
    v1 = e1 - np.asarray(a, dtype=float)
    v12 = e2 - e1
    l_AE1 = float(np.linalg.norm(v1))
    cos_a = float(v1 @ v12) / (l_AE1 * l_E1E2)
    return WinchParams(
        k_w=coiling_coefficient(r_w, mu),
        l_u0=l_u0,
        q0=q0,
        q_max=max_angle(l_E1E2, mu),
        l_AE1=l_AE1,
        l_E1E2=l_E1E2,
        alpha_E1=math.acos(max(-1.0, min(1.0, cos_a))),
    )


# ---- the quadratic (eq. 19-32, corrected) --------------------------------------------------
def l_AE(p, q):
    """|e(q) - a| from the law of cosines on triangle A E1 E (left side of eq. 22) [m].

    .. math:: l_d(q) = \\sqrt{l_{AE_1}^2 + 2 s\\, l_{AE_1} \\cos\\alpha_{E_1} + s^2},
        \\quad s = \\frac{q}{q_{max}} l_{E_1E_2}

    (Métillon 2022 eq. 15 with eq. 12 and 22).

    Parameters
    ----------
    p : WinchParams
    q : float or array_like (...) [rad]
        Drum angles.

    Returns
    -------
    l_d : ndarray (...) [m]
        Cable length from the drum exit point E(q) to the pulley entry point A.
    """
    s = np.asarray(q, dtype=float) / p.q_max * p.l_E1E2
    return np.sqrt(p.l_AE1**2 + 2 * s * p.l_AE1 * math.cos(p.alpha_E1) + s**2)


def l_pm0(p):
    """Initial pulley-to-platform length from |e(q0) - a| = l_u0 - l_pm0 (eq. 15-16) [m].

    .. math:: l_{pm_0} = l_{u_0} - \\lVert e(q_0) - a \\rVert  \\quad \\text{(Métillon 2022 eq. 15-16)}

    Parameters
    ----------
    p : WinchParams

    Returns
    -------
    l_pm0 : float [m]
        Cable length beyond the pulley entry point A in the initial state (negative when the
        parameters are inconsistent, see ``check_range``).
    """
    return p.l_u0 - float(l_AE(p, p.q0))


def coefficients(p, l_pm):
    """Coefficients a, b, c of a q^2 + b q + c = 0 (eq. 23-26 with the eq. 19 sign corrected).

    .. math:: a = \\frac{l_{E_1E_2}^2}{q_{max}^2} - k_w^2, \\quad
        b = \\frac{2}{q_{max}} l_{AE_1} l_{E_1E_2} \\cos\\alpha_{E_1} + 2 k_w X, \\quad
        c = l_{AE_1}^2 - X^2, \\quad X = l_{u_0} + k_w q_0 - l_{pm}

    (Métillon 2022 eq. 24-26).

    Parameters
    ----------
    p : WinchParams
    l_pm : float or array_like (...) [m]
        Desired cable lengths beyond the pulley entry point A.

    Returns
    -------
    a : ndarray (...) [m^2/rad^2]
        Broadcast to the shape of l_pm; equal to -r_w^2 when q_max and k_w come from eq. (13) and
        (18) (eq. 27 corrected).
    b : ndarray (...) [m^2/rad]
    c : ndarray (...) [m^2]
    """
    X = p.l_u0 + p.k_w * p.q0 - np.asarray(l_pm, dtype=float)
    a = p.l_E1E2**2 / p.q_max**2 - p.k_w**2
    b = 2.0 / p.q_max * p.l_AE1 * p.l_E1E2 * math.cos(p.alpha_E1) + 2.0 * p.k_w * X
    c = p.l_AE1**2 - X**2
    return np.broadcast_to(a, X.shape).astype(float), b, c


def roots(p, l_pm):
    """Both roots (q1, q2) = (-b +/- sqrt(Delta)) / (2a) (eq. 28-30 corrected) [rad].

    q1 is the physical root (through (l_pm0, q0)); NaN where Delta < 0.

    .. math:: \\Delta = b^2 - 4 a c, \\quad q_{1,2} = \\frac{-b \\pm \\sqrt{\\Delta}}{2a}
        \\quad \\text{(Métillon 2022 eq. 28-30, denominator corrected)}

    Parameters
    ----------
    p : WinchParams
    l_pm : float or array_like (...) [m]
        Desired cable lengths beyond the pulley entry point A.

    Returns
    -------
    q1 : ndarray (...) [rad]
        Physical root: the drum angle that realises l_pm. Not checked against [0, q_max].
    q2 : ndarray (...) [rad]
        The other root (Fig. 8: the platform would have passed through the pulley).
    """
    a, b, c = coefficients(p, l_pm)
    disc = b**2 - 4 * a * c
    sq = np.sqrt(np.where(disc >= 0, disc, np.nan))
    return (-b + sq) / (2 * a), (-b - sq) / (2 * a)


def q_no_winch(p, l_pm):
    """Joint angle of the model that neglects the winch geometry, eq. (32) [rad].

    .. math:: q_{nw} = q_0 + \\frac{l_{pm_0} - l_{pm}}{k_w} \\quad \\text{(Métillon 2022 eq. 32)}

    Parameters
    ----------
    p : WinchParams
    l_pm : float or array_like (...) [m]
        Desired cable lengths beyond the pulley entry point A.

    Returns
    -------
    q_nw : ndarray (...) [rad]
        Drum angle that a constant exit-to-pulley length |E A| would need.
    """
    return p.q0 + (l_pm0(p) - np.asarray(l_pm, dtype=float)) / p.k_w


def length_error(p, l_pm):
    """Uncoiled length error dl = k_w (q1 - q_nw) (Métillon 2022 eq. 31) [m].

    Parameters
    ----------
    p : WinchParams
    l_pm : float or array_like (...) [m]
        Desired cable lengths beyond the pulley entry point A.

    Returns
    -------
    dl : ndarray (...) [m]
        Length error of the model that neglects the winch geometry (with Table 1: 1.47 mm at
        l_pm = 0 and -0.82 mm at 5 m; Fig. 7b prints 1.46 mm and -0.82 mm).
    """
    q1, _ = roots(p, l_pm)
    return p.k_w * (q1 - q_no_winch(p, l_pm))


def l_pm_of_q(p, q):
    """Length l_pm [m] beyond the pulley entry point A that the drum angle q [rad] realises, with the
    exit point's motion (eq. 15-17, 22 with the eq. 19 sign corrected):

    .. math:: l_{pm}(q) = l_{u0} + k_w (q_0 - q) - \\lVert e(q) - a \\rVert

    The inverse is ``roots(p, l_pm)[0]`` (the physical root q1).

    Parameters
    ----------
    p : WinchParams
    q : float or array_like (...) [rad]
        Drum angles.

    Returns
    -------
    l_pm : ndarray (...) [m]
        Cable length beyond the pulley entry point A (Métillon 2022 eq. 14-17).
    """
    q = np.asarray(q, dtype=float)
    return p.l_u0 + p.k_w * (p.q0 - q) - l_AE(p, q)


def l_pm_of_q_no_winch(p, q):
    """Length l_pm [m] that a controller neglecting the exit point's motion expects from the drum
    angle q [rad]: the inverse of eq. (32), l_pm = l_pm0 - k_w (q - q0).

    Parameters
    ----------
    p : WinchParams
    q : float or array_like (...) [rad]
        Drum angles.

    Returns
    -------
    l_pm : ndarray (...) [m]
        Cable length beyond A that the no-winch model (Métillon 2022 eq. 32) assigns to q.
    """
    return l_pm0(p) - p.k_w * (np.asarray(q, dtype=float) - p.q0)


def check_range(p, lpm_from, lpm_to):
    """Refuse winch parameters or a range of l_pm [m] where the model has no physical answer: an
    initial length l_pm0 < 0, or a physical drum angle q1 that is not real or leaves [0, q_max]
    (the cable would be fully coiled or uncoiled). Raises CdprError naming the values.

    The range is sampled at 1001 evenly spaced lengths (``roots``, Métillon 2022 eq. 28-30).

    Parameters
    ----------
    p : WinchParams
    lpm_from : float [m]
        First length l_pm of the range.
    lpm_to : float [m]
        Last length l_pm of the range.

    Returns
    -------
    None
        Returns only when the whole range is valid; otherwise raises CdprError.
    """
    lp0 = l_pm0(p)
    if not math.isfinite(lp0) or lp0 < 0:
        raise CdprError(
            f"these winch parameters give an initial length l_pm0 = {lp0:.4g} m < 0 (l_u0 must exceed |A E(q0)|); check l_u0_m, l_AE1_m, l_E1E2_m"
        )
    l_pm = np.linspace(lpm_from, lpm_to, 1001)
    q1, _ = roots(p, l_pm)
    bad = ~np.isfinite(q1) | (q1 < 0) | (q1 > p.q_max)
    if bad.any():
        at = float(l_pm[np.argmax(bad)])
        raise CdprError(
            f"at l_pm = {at:.4g} m the drum angle q1 = {float(q1[np.argmax(bad)]):.4g} rad leaves [0, q_max = {p.q_max:g}] rad "
            f"(the cable would be fully coiled or uncoiled): choose l_pm in a range the drum can hold"
        )


# ---- the spool winch (RepRapFirmware's Hangprinter kinematics, M666 Q R U O L H) ------------
# A spool of radius r0 (with the mover at the origin) winds O lines side by side; paying out a line
# unwinds the wound line's cross-section, so the spool radius r shrinks as line comes off. Line of
# cross-section a wound on a spool of height h fills an annulus: pi (r0^2 - r^2) h = O a s for the
# released length s of each of the O lines, i.e. r^2 = r0^2 - O Q s with the buildup factor
# Q = a / (pi h) [m] (M666 Q; RepRapFirmware's own comment: Q = 0.0078 mm for a 0.5 mm line on an
# 8 mm high spool). The spool turns by dphi = ds / r, so
#     phi(s) = integral_0^s ds' / sqrt(r0^2 - O Q s') = 2 (r0 - sqrt(r0^2 - O Q s)) / (O Q),
# and back s(phi) = r0 phi - O Q phi^2 / 4. This is the model of RepRapFirmware's
# HangprinterKinematics.cpp (Duet3D/RepRapFirmware, src/Movement/Kinematics; CartesianToMotorSteps
# and MotorPosToLinePos, with k2 = -U O Q and k0 = 2 (U J H / (2 pi L)) / k2 steps), derived here
# and written independently.
def spool_angle(motor_deg, motor_teeth, spool_teeth):
    """Spool angle from the motor shaft angle through the gears, phi = (pi / 180) theta L / H [rad].

    .. math:: \\varphi = \\frac{\\pi}{180} \\, \\theta_{deg} \\, \\frac{L}{H}

    The motor gear has L teeth and the spool gear H (M666 L and H): the motor turns H / L times per
    spool turn.

    Parameters
    ----------
    motor_deg : float or array_like (...) [deg]
        Motor shaft angles (the encoder's reading, relative to the reference).
    motor_teeth : float or array_like [-]
        Teeth of the motor gear L.
    spool_teeth : float or array_like [-]
        Teeth of the spool gear H.

    Returns
    -------
    phi : ndarray (...) [rad]
        Spool angles.
    """
    return np.deg2rad(np.asarray(motor_deg, dtype=float)) * np.asarray(motor_teeth, dtype=float) / spool_teeth


def motor_degrees(phi, motor_teeth, spool_teeth):
    """Motor shaft angle of a spool angle, theta = (180 / pi) phi H / L [deg] (inverse of
    ``spool_angle``).

    .. math:: \\theta_{deg} = \\frac{180}{\\pi} \\, \\varphi \\, \\frac{H}{L}

    Parameters
    ----------
    phi : float or array_like (...) [rad]
        Spool angles.
    motor_teeth : float or array_like [-]
        Teeth of the motor gear L.
    spool_teeth : float or array_like [-]
        Teeth of the spool gear H.

    Returns
    -------
    motor_deg : ndarray (...) [deg]
        Motor shaft angles.
    """
    return np.rad2deg(np.asarray(phi, dtype=float)) * np.asarray(spool_teeth, dtype=float) / motor_teeth


def released_line(phi, r0, Q, lines_per_spool=1):
    """Line released by a spool turned by phi from the origin, with line buildup [m].

    .. math:: s(\\varphi) = r_0 \\varphi - \\frac{O Q}{4} \\varphi^2,
        \\qquad r(\\varphi) = r_0 - \\frac{O Q}{2} \\varphi

    from r^2 = r0^2 - O Q s and ds = r dphi (module comment above; RepRapFirmware's
    HangprinterKinematics ``MotorPosToLinePos`` with M666 Q, R, O). Defined while the spool radius
    stays positive: phi < 2 r0 / (O Q); NaN beyond (the spool would be empty).

    Parameters
    ----------
    phi : float or array_like (...) [rad]
        Spool angles from the reference (positive: line paid out).
    r0 : float or array_like [m]
        Spool radius at the reference (mover at the origin; M666 R).
    Q : float or array_like [m]
        Buildup factor (M666 Q, given there in mm): the squared radius drops by O Q per metre of
        released line. Q = 0: a spool of constant radius, s = r0 phi.
    lines_per_spool : int or array_like [-]
        Lines wound side by side on the spool, O (M666 O).

    Returns
    -------
    s : ndarray (...) [m]
        Released length of each line (negative when line is wound in).
    """
    phi = np.asarray(phi, dtype=float)
    oq = np.asarray(lines_per_spool, dtype=float) * Q
    r = r0 - 0.5 * oq * phi  # the spool radius at phi
    return np.where(r > 0, phi * (r0 - 0.25 * oq * phi), np.nan)


def spool_angle_of_line(s, r0, Q, lines_per_spool=1):
    """Spool angle that releases the length s of line, the inverse of ``released_line`` [rad].

    .. math:: \\varphi(s) = \\frac{2 \\left(r_0 - \\sqrt{r_0^2 - O Q s}\\right)}{O Q}
        = \\frac{2 s}{r_0 + \\sqrt{r_0^2 - O Q s}}

    (the second form, used here, has no cancellation and holds at Q = 0: phi = s / r0;
    RepRapFirmware's HangprinterKinematics ``CartesianToMotorSteps``: steps = k0 (sqrt(R^2 + k2 s / U)
    - R) with k2 = -U O Q). NaN where r0^2 < O Q s (more line than the spool holds).

    Parameters
    ----------
    s : float or array_like (...) [m]
        Released length of each line (negative: wound in).
    r0 : float or array_like [m]
        Spool radius at the reference (M666 R).
    Q : float or array_like [m]
        Buildup factor (M666 Q).
    lines_per_spool : int or array_like [-]
        Lines per spool, O (M666 O).

    Returns
    -------
    phi : ndarray (...) [rad]
        Spool angles.
    """
    s = np.asarray(s, dtype=float)
    disc = r0**2 - np.asarray(lines_per_spool, dtype=float) * Q * s
    root = np.sqrt(np.where(disc > 0, disc, np.nan))
    return 2.0 * s / (r0 + root)


def spool_rest_length(p, motor_deg, L0_ref):
    """Rest length of a spool's cable from its motor angle: L0 = L0_ref + s(phi) / U [m].

    .. math:: L_0 = L_{0,ref} + \\frac{1}{U}\\left(r_0 \\varphi - \\frac{O Q}{4}\\varphi^2\\right),
        \\quad \\varphi = \\frac{\\pi}{180} \\theta_{deg} \\frac{L}{H}

    The line runs U times between anchor and mover (a block-and-tackle of U strands, M666 U), so
    the anchor-mover rest length changes by the released line / U.

    Parameters
    ----------
    p : SpoolParams
        r0 [m], Q [m], U, O, motor_teeth L, spool_teeth H.
    motor_deg : float or array_like (...) [deg]
        Motor angles relative to the reference.
    L0_ref : float or array_like [m]
        Rest length at the reference (motor angle 0).

    Returns
    -------
    L0 : ndarray (...) [m]
        NaN where the spool would be empty.
    """
    phi = spool_angle(motor_deg, p.motor_teeth, p.spool_teeth)
    return L0_ref + released_line(phi, p.r0, p.Q, p.lines_per_spool) / p.U


def spool_motor_angle(p, L0, L0_ref):
    """Motor angle that gives a spool's cable the rest length L0, the inverse of
    ``spool_rest_length`` [deg].

    .. math:: \\theta_{deg} = \\frac{180}{\\pi} \\frac{H}{L}
        \\frac{2 U (L_0 - L_{0,ref})}{r_0 + \\sqrt{r_0^2 - O Q U (L_0 - L_{0,ref})}}

    Parameters
    ----------
    p : SpoolParams
    L0 : float or array_like (...) [m]
        Rest lengths.
    L0_ref : float or array_like [m]
        Rest length at the reference (motor angle 0).

    Returns
    -------
    motor_deg : ndarray (...) [deg]
        NaN where the spool cannot release that much line.
    """
    s = p.U * (np.asarray(L0, dtype=float) - L0_ref)
    phi = spool_angle_of_line(s, p.r0, p.Q, p.lines_per_spool)
    return motor_degrees(phi, p.motor_teeth, p.spool_teeth)
