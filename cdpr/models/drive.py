"""The winch in the chain: drum angles <-> commanded rest lengths of a robot's cables.

A robot file may give each cable a winch (Métillon et al. 2022, Table 1 keys). The drum pays out
the uncoiled length l_u(q) = l_u0 + k_w (q0 - q) (winch seed eq. 17); of it, the segment from the
drum's exit point e(q) to the pulley entry point a is |e(q) - a| (eq. 22), and the rest,

    l_pm(q) = l_u(q) - |e(q) - a|,

lies beyond the pulley. In the robot model the cable's rest length from the winch exit C to the
platform is L0 = d + l_pm: the dead length d (C to the pulley joint, as in the paper's reading)
plus the rest length beyond it. So a commanded rest length L0_i maps to the drum angle
q_i = q1(l_pm = L0_i - d_i) (the physical root, ``winch.roots``), and the controller that
neglects the exit point's motion commands q_nw (``winch.q_no_winch``, eq. 32). A robot commanded
in drum angles realises L0 = d + l_pm(q) with the winch's true geometry; commanding q_nw therefore
adds the winch's length error δl = k_w (q1 - q_nw) (eq. 31) to the pose error.

A spool winch (``winch: {kind: spool}``, RepRapFirmware's Hangprinter kinematics) is the encoder
map instead: the motor angle theta_i [deg] turns the spool by phi_i = theta_i L / H, which releases
s_i = r0 phi_i - O Q phi_i^2 / 4 of line (``winch.released_line``), and the U strands between anchor
and platform lengthen by s_i / U, so L0_i = L0_ref,i + s_i / U, exactly and in every model (the
rigid-line model too, where the rest length is the line length). L0_ref,i is the rest length at
theta = 0, by default the standard model's length L_TS,i with the platform at the origin (the
Hangprinter's reference: the encoders are zeroed with the mover at the origin, and its firmware
commands straight lines).

References
----------
Métillon, M., Charron, C., Subrin, K., Caro, S. (2022). Geometrical modelling of a cable-driven
parallel robot winch. 25e Congrès Français de Mécanique, hal-03758222.
"""

from __future__ import annotations

import numpy as np

from cdpr.errors import CdprError
from cdpr.models import winch
from cdpr.models.inverse import L_TS


def _on_every_cable(robot, items, what):
    """``items`` (one per cable) when none is None, else CdprError naming the cables without one:
    "cables [..] have no <what>" (``what`` also says what to give)."""
    missing = [i + 1 for i, x in enumerate(items) if x is None]
    if missing:
        raise CdprError(f"{robot.source}: cables {missing} have no {what}")
    return items


def _winches(robot):
    return _on_every_cable(
        robot, robot.winches, "winch; give 'winch:' in the robot file (winch: {} is Table 1's)"
    )


def drum_angles(robot, L0):
    """Drum angles that realise the rest lengths L0, with and without the exit point's motion.

    Parameters
    ----------
    robot : Robot
        Every cable needs a winch.
    L0 : array (N, m) [m]
        Commanded rest lengths, winch exit to platform.

    Returns
    -------
    q : array (N, m) [rad]
        The physical root q1 of the winch seed's quadratic (eq. 29-30 corrected) for
        l_pm = L0 - d; NaN where the drum cannot hold that length (no real root or q1 outside
        [0, q_max]).
    q_nw : array (N, m) [rad]
        The angle of the model that neglects the winch geometry (eq. 32).
    """
    L0 = np.atleast_2d(np.asarray(L0, dtype=float))
    q = np.full(L0.shape, np.nan)
    q_nw = np.full(L0.shape, np.nan)
    for i, p in enumerate(_winches(robot)):  # one loop per cable, vectorised over points
        l_pm = L0[:, i] - robot.d[i]
        q1, _ = winch.roots(p, l_pm)
        q[:, i] = np.where((q1 >= 0) & (q1 <= p.q_max), q1, np.nan)
        q_nw[:, i] = winch.q_no_winch(p, l_pm)
    return q, q_nw


def rest_lengths_from_angles(robot, q, model="winch"):
    """Rest lengths L0 [m], shape (N, m), that drum angles q (N, m) [rad] realise.

    ``model="winch"``: the drum's true geometry, L0 = d + l_pm(q) (``winch.l_pm_of_q``);
    ``model="no_winch"``: what a controller that neglects the exit point's motion believes
    (``winch.l_pm_of_q_no_winch``). Angles outside [0, q_max] raise CdprError.

    Parameters
    ----------
    robot : Robot
        Every cable needs a winch.
    q : array_like (N, m) [rad]
        Drum angles, one column per cable.
    model : {"winch", "no_winch"}
        "winch": Métillon 2022 eq. (14)-(17) with the moving exit point (eq. 12, 15); "no_winch":
        the inverse of eq. (32). Any value other than "winch" is taken as "no_winch".

    Returns
    -------
    L0 : ndarray (N, m) [m]
        Rest lengths from the winch exit C_i to the platform, d_i + l_pm,i(q_i).
    """
    if model not in ("winch", "no_winch"):
        raise CdprError(f"unknown winch model {model!r}; allowed: winch, no_winch")
    q = np.atleast_2d(np.asarray(q, dtype=float))
    ws = _winches(robot)
    if q.shape[-1] != robot.m:
        raise CdprError(f"{robot.m} drum angles needed (one per cable), got {q.shape[-1]}")
    out = np.empty(q.shape)
    for i, p in enumerate(ws):
        if not ((q[:, i] >= 0) & (q[:, i] <= p.q_max)).all():
            raise CdprError(f"drum angle of cable {i + 1} outside [0, q_max = {p.q_max:g}] rad")
        f = winch.l_pm_of_q if model == "winch" else winch.l_pm_of_q_no_winch
        out[:, i] = robot.d[i] + f(p, q[:, i])
    return out


def has_winches(robot):
    """True when every cable of ``robot`` has a winch (the robot file's ``winch:``), False when none
    has; a robot with winches on some cables only raises CdprError (``_winches``).

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    bool
    """
    ws = robot.winches
    if all(w is None for w in ws):
        return False
    _winches(robot)
    return True


def realised_rest_lengths(robot, L_cmd):
    """Rest lengths the drums realise when a controller that neglects the exit point's motion is
    asked for the rest lengths L_cmd, and their derivatives.

    The controller turns drum i to q_nw,i = q0 + (l_pm0 - (L_cmd,i - d_i)) / k_w (eq. 32); the drum's
    true geometry then pays out l_pm(q_nw) = l_u0 + k_w (q0 - q_nw) - |e(q_nw) - a| (eq. 14-17, 22),
    so the realised rest length is

    .. math:: L0_i = d_i + l_{pm}(q_{nw,i}) = L_{cmd,i} + l_{AE}(q_0) - l_{AE}(q_{nw,i}),

    .. math:: \\frac{\\partial L0_i}{\\partial L_{cmd,i}} = 1 + \\frac{l_{AE}'(q_{nw,i})}{k_w},
              \\quad \\frac{\\partial L0_i}{\\partial d_i} = -\\frac{l_{AE}'(q_{nw,i})}{k_w},
              \\quad l_{AE}'(q) = \\frac{s'(l_{AE_1}\\cos\\alpha_{E_1} + s)}{l_{AE}(q)},
              \\quad s = \\frac{q}{q_{max}} l_{E_1E_2},\\ s' = \\frac{l_{E_1E_2}}{q_{max}}.

    L0 - L_cmd is the winch's length error: to first order in l_AE'/k_w it is δl = k_w (q1 - q_nw)
    (eq. 31, ``winch.length_error``; 1.47 mm at l_pm = 0 to -0.82 mm at 5 m with Table 1). The
    dead length d_i is the robot's own (the commanded lengths are rest lengths in the robot's
    frame, as without a winch).

    Parameters
    ----------
    robot : Robot
        Every cable needs a winch.
    L_cmd : array_like, shape (N, m) [m]
        Commanded rest lengths, winch exit to platform.

    Returns
    -------
    L0 : ndarray, shape (N, m) [m]
        Realised rest lengths; NaN where q_nw leaves [0, q_max] (the drum cannot pay that out).
    dL0_dL : ndarray, shape (N, m) [m/m]
        dL0_i / dL_cmd,i.
    dL0_dd : ndarray, shape (N, m) [m/m]
        dL0_i / dd_i at fixed L_cmd.

    References
    ----------
    Métillon et al. 2022, eq. (12), (14)-(17), (22), (31)-(32).
    """
    L_cmd = np.atleast_2d(np.asarray(L_cmd, dtype=float))
    if L_cmd.shape[-1] != robot.m:
        raise CdprError(f"{robot.m} commanded lengths needed (one per cable), got {L_cmd.shape[-1]}")
    L0 = np.empty(L_cmd.shape)
    slope = np.empty(L_cmd.shape)
    for i, p in enumerate(_winches(robot)):  # one loop per cable, vectorised over points
        q = winch.q_no_winch(p, L_cmd[:, i] - robot.d[i])
        inside = (q >= 0) & (q <= p.q_max)
        ld = winch.l_AE(p, q)
        s = q / p.q_max * p.l_E1E2
        d_ld = p.l_E1E2 / p.q_max * (p.l_AE1 * np.cos(p.alpha_E1) + s) / ld
        L0[:, i] = np.where(inside, L_cmd[:, i] + winch.l_AE(p, p.q0) - ld, np.nan)
        slope[:, i] = d_ld / p.k_w
    return L0, 1.0 + slope, -slope


def commanded_for(robot, L0, tol=1e-13, maxiter=50):
    """The commanded lengths L_cmd whose realised rest lengths (``realised_rest_lengths``) are L0: what
    a model that knows the winch asks the no-winch controller for. Fixed-point iteration
    L_cmd <- L_cmd - (L0(L_cmd) - L0), a contraction of ratio |l_AE'| / k_w (about 5e-4 with
    Table 1).

    Parameters
    ----------
    robot : Robot
        Every cable needs a winch.
    L0 : array_like, shape (N, m) [m]
        Wanted rest lengths.
    tol : float [m]
    maxiter : int

    Returns
    -------
    L_cmd : ndarray, shape (N, m) [m]
        NaN where the drum cannot realise L0.
    """
    L0 = np.atleast_2d(np.asarray(L0, dtype=float))
    L = L0.copy()
    for _ in range(maxiter):
        got, dL, _ = realised_rest_lengths(robot, L)
        step = (got - L0) / dL
        L = L - step
        if not (np.abs(step) > tol).any():  # NaN steps (outside the drum) stop too
            break
    return L


# ---- spools (RepRapFirmware's Hangprinter kinematics) --------------------------------------
def has_spools(robot):
    """True when every cable of ``robot`` has a spool winch (``winch: {kind: spool}``), False when
    none has; a robot with spools on some cables only raises CdprError.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    bool
    """
    sp = robot.spools
    if all(p is None for p in sp):
        return False
    _on_every_cable(robot, sp, "spool; motor angles need a spool on every cable")
    return True


def spool_reference_lengths(robot):
    """Rest lengths at motor angle 0 [m]: the standard model's lengths L_TS,i = |A_i - B_i| + d_i with
    the platform at the origin (Paty 2021 eq. 2, ``inverse.L_TS``), where a Hangprinter's encoders
    are zeroed.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    L0_ref : ndarray (m,) [m]
    """
    return np.asarray(L_TS(robot, np.zeros((1, 3))), dtype=float).reshape(-1)[: robot.m]


def spool_rest_lengths(robot, motor_deg, L0_ref=None):
    """Rest lengths that motor angles realise through every cable's spool (``winch.spool_rest_length``).

    .. math:: L_{0,i} = L_{0,ref,i} + \\frac{1}{U_i}\\left(r_{0,i} \\varphi_i
        - \\frac{O_i Q_i}{4} \\varphi_i^2\\right), \\quad
        \\varphi_i = \\frac{\\pi}{180} \\theta_i \\frac{L_i}{H_i}

    Parameters
    ----------
    robot : Robot
        Every cable needs a spool.
    motor_deg : array_like (N, m) [deg]
        Motor angles relative to the reference, one column per cable (positive: line paid out).
    L0_ref : array_like (m,) [m], optional
        Rest lengths at motor angle 0 (default ``spool_reference_lengths``).

    Returns
    -------
    L0 : ndarray (N, m) [m]
        NaN where a spool would be empty.
    """
    th = np.atleast_2d(np.asarray(motor_deg, dtype=float))
    if not has_spools(robot):
        raise CdprError(f"{robot.source}: motor angles need spool winches (winch: {{kind: spool, ...}})")
    if th.shape[-1] != robot.m:
        raise CdprError(f"{robot.m} motor angles needed (one per cable), got {th.shape[-1]}")
    ref = spool_reference_lengths(robot) if L0_ref is None else np.asarray(L0_ref, dtype=float)
    out = np.empty(th.shape)
    for i, p in enumerate(robot.spools):  # one loop per cable, vectorised over samples
        out[:, i] = winch.spool_rest_length(p, th[:, i], ref[i])
    return out


def spool_motor_angles(robot, L0, L0_ref=None):
    """Motor angles that give every cable the rest length L0 through its spool, the inverse of
    ``spool_rest_lengths`` (``winch.spool_motor_angle``).

    .. math:: \\theta_i = \\frac{180}{\\pi} \\frac{H_i}{L_i}
        \\frac{2 s_i}{r_{0,i} + \\sqrt{r_{0,i}^2 - O_i Q_i s_i}}, \\quad
        s_i = U_i (L_{0,i} - L_{0,ref,i})

    Parameters
    ----------
    robot : Robot
        Every cable needs a spool.
    L0 : array_like (N, m) [m]
        Rest lengths.
    L0_ref : array_like (m,) [m], optional
        Rest lengths at motor angle 0 (default ``spool_reference_lengths``).

    Returns
    -------
    motor_deg : ndarray (N, m) [deg]
        NaN where a spool cannot release that much line.
    """
    L0 = np.atleast_2d(np.asarray(L0, dtype=float))
    if not has_spools(robot):
        raise CdprError(f"{robot.source}: motor angles need spool winches (winch: {{kind: spool, ...}})")
    if L0.shape[-1] != robot.m:
        raise CdprError(f"{robot.m} rest lengths needed (one per cable), got {L0.shape[-1]}")
    ref = spool_reference_lengths(robot) if L0_ref is None else np.asarray(L0_ref, dtype=float)
    out = np.empty(L0.shape)
    for i, p in enumerate(robot.spools):
        out[:, i] = winch.spool_motor_angle(p, L0[:, i], ref[i])
    return out
