"""Physical equilibrium of a rigid 6-DoF platform on m elastic cables with pulleys at any orientation.

The generalisation of ``cdpr.models.equilibrium`` (the point-mass physical mode, which is the
special case b_i = 0, c = 0: the rotation then plays no part and the moment rows of the wrench
matrix vanish, so the solver works on the 3 force rows, "rank(W) = 3: reduce its rows"). The winches
hold commanded rest lengths L0_i (by default the standard model's L_TS,i at the desired pose, the
paper's study). The platform settles at the pose (p*, R*) where

    W(p*, R*) t + w_ext(R*) = 0,   t_i = (E_i S_i / L0_i) max(0, L_TE,i(B_i) - L0_i),   B_i = p + R b_i

with W the 6 x m wrench matrix (``platform.wrench_matrix``; column [u_i ; r_i x u_i], r_i = R b_i,
u_i from B_i toward the exit point D_i of the pulley, ``pulleys.total_length_and_direction`` at
B_i) and w_ext the gravity wrench at the centre of mass (``platform.external_wrench``).

Solver
------
Semismooth Newton on the force *and moment* balance F6 with its analytic generalised Jacobian in
the pose increments x = (dp, dphi) (dphi a base-frame rotation vector, R <- exp([dphi]x) R):
dB_i = dp - [r_i]x dphi, and with G_i = t_i du_i/dB + (E_i S_i / L0_i) a_i u_i (dL_i/dB)^T
(``statics.direction_gradient``, ``statics.length_gradient``),

    dF/dx = sum_i G_i [I, -[r_i]x]
    dM/dx = sum_i [r_i]x G_i [I, -[r_i]x] + [0, sum_i t_i (u_i r_i^T... )]  (see ``_jacobian``)

The step is the least-squares (pseudo-inverse) Newton step of the 6 x 6 system (a neutral mode,
such as the rotation of a platform hanging from one point about the vertical, gets no step); it
is globalised by an Armijo line search on the energy V = sum_i E_i S_i/(2 L0_i) max(0, e_i)^2 -
f . (p + R c), as in the point-mass mode (steps under ``LS_SKIP`` taken whole; where the Newton
step does not descend V, a scaled gradient step). A point converges when |F| <= FTOL_REL |f| and
|M| <= FTOL_REL |f| l (l the platform's size), or on the point-mass mode's step rules.

Several equilibria: a robot with slack cables can hang in more than one pose. Where the converged
Hessian -dF6/dx is not positive definite or fewer than 6 cables are taut (platform robots only),
the point is solved again from ``RESTARTS`` (the desired pose turned by +-``RESTART_ANGLE`` about
x, y, z); the lowest-energy equilibrium found is returned, ``unique`` is False where another one
(more than ``DISTINCT`` apart) exists, and the others are listed under ``alternatives``.

Statuses (physical mode's): ``ok``, ``over_tension``, ``inaccessible``, ``not_converged``. For a
suspended point-mass robot, ``inaccessible`` keeps its rules (``equilibrium.statuses``: outside the
anchors' hull or at or above the lowest anchor); for every other robot a pose is inaccessible only
when the equilibrium is not finite or lies inside a sheave, and ``not_converged`` when Newton
found no equilibrium.

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (eq. 2-5, 10-14).

Pott, A. (2018). Cable-Driven Parallel Robots: Theory and Application. Springer, ch. 3 (wrench
matrix, elastic cables).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from cdpr.models.equilibrium import (
    FTOL_REL,
    LS_SKIP,
    PHYSICAL_DEFAULTS,
    ST,
    START_BELOW,
    TAUT_MIN,
    backtrack,
    hull_halfplanes,
    statuses,
)
from cdpr.models.platform import attachment_points, rotation_error, rotation_matrix, rotvec_of, skew
from cdpr.models.pulleys import pulley_state, total_length_and_direction
from cdpr.models.results import STATUSES
from cdpr.models.statics import direction_gradient, length_gradient, solve3

#: Restart orientations: the desired one turned by +-RESTART_ANGLE [rad] about x, y and z.
RESTART_ANGLE = np.radians(20.0)
RESTARTS = np.array([[s * RESTART_ANGLE * (i == a) for i in range(3)] for a in range(3) for s in (1, -1)])
#: Two equilibria are distinct when their poses differ by more than this [m] or [rad].
DISTINCT = 1e-6
#: Relative singular-value cut of the least-squares Newton step.
RCOND = 1e-12


def pose_arrays(robot, p, rotvec=None):
    """Positions and orientations of desired poses (no paper equation).

    Parameters
    ----------
    robot : Robot
        Unused (kept for a signature parallel to the other pose helpers).
    p : array_like (N, 3) or (N, 6) [m, rad]
        Positions, or poses (x, y, z, rx, ry, rz).
    rotvec : array_like (N, 3) or (3,) [rad], optional
        Rotation vectors (default identity; ignored when p holds poses).

    Returns
    -------
    p : ndarray (N, 3) [m]
    R : ndarray (N, 3, 3) [-]
    """
    p = np.atleast_2d(np.asarray(p, dtype=float))
    if p.shape[1] == 6:
        p, rotvec = p[:, :3], p[:, 3:]
    rv = np.zeros_like(p) if rotvec is None else np.broadcast_to(np.asarray(rotvec, dtype=float), p.shape)
    return np.ascontiguousarray(p), rotation_matrix(rv)


def pose_state(robot, p, R):
    """The extended inverse model (``pulleys.pulley_state``) of every cable at poses (p, R): the
    attachment points B (N, m, 3) [m] and the PulleyState at them.

    Parameters
    ----------
    robot : Robot
    p : ndarray (N, 3) [m]
        Reference points.
    R : ndarray (N, 3, 3) [-]
        Orientations.

    Returns
    -------
    B : ndarray (N, m, 3) [m]
    state : PulleyState
        Arrays (N, m); L_TE is Paty 2021 eq. (5) at B_i.
    """
    a = robot.arrays
    B = attachment_points(p, R, a.b)
    return B, pulley_state(B, *_args(robot), per_cable=True)


def _args(robot):
    a = robot.arrays
    frame = None if robot.suspended_point_mass else a.frame
    return a.A, a.kind, a.h, a.r_p, a.d, a.inward, frame


def L_TS_pose(robot, p, R):
    """Standard total lengths L_TS,i = |B_i - A_i| + d_i at poses (p, R) (Paty 2021 eq. 2 with
    B_i = p + R b_i in place of P).

    Parameters
    ----------
    robot : Robot
    p : ndarray (N, 3) [m]
        Reference points.
    R : ndarray (N, 3, 3) [-]
        Orientations.

    Returns
    -------
    L_TS : ndarray (N, m) [m]
    """
    B = attachment_points(p, R, robot.arrays.b)
    return np.linalg.norm(B - robot.A, axis=-1) + robot.d


class Cables6:
    """Force/moment balance, energy and Jacobian of a robot's cables at poses."""

    def __init__(self, robot):
        a = robot.arrays
        self.robot = robot
        self.args = _args(robot)
        self.b, self.com = a.b, a.com
        self.ES = a.ES
        self.f = robot.platform.w_ext
        self.ftol = FTOL_REL * float(np.linalg.norm(self.f))
        size = max(float(np.linalg.norm(a.b, axis=1).max()), float(np.linalg.norm(a.com)))
        self.size = size if size > 0 else 1.0
        self.rigid = not robot.point_mass
        self.suspended = robot.suspended_point_mass
        self.z_top = float(a.A[:, 2].min())

    def evaluate(self, p, R, L0, p_ref, jacobian=True):
        """Cables at poses (p (N, 3), R (N, 3, 3)) with rest lengths L0 (N, m): F, M (N, 3), t (N, m),
        merit V (N,) [J] relative to p_ref (N, 3) and, with ``jacobian``, Fn, J (N, 6, 6), grad (N, 6)
        and kappa (N, 2) (stiffness bounds of translation and rotation)."""
        r = np.einsum("nab,mb->nma", R, self.b)
        B = p[:, None, :] + r
        g = total_length_and_direction(B, *self.args, per_cable=True)
        e = g.L_TE - L0
        k = self.ES / L0
        taut = e > 0.0
        t = np.where(taut, k * e, 0.0)
        rc = R @ self.com
        F = np.einsum("nj,nja->na", t, g.u) + self.f
        M = np.einsum("nj,nja->na", t, np.cross(r, g.u)) + np.cross(rc, self.f)
        merit = -(p - p_ref + rc) @ self.f + 0.5 * (k * np.where(taut, e, 0.0) ** 2).sum(axis=1)
        if self.suspended:
            merit = np.where(p[:, 2] < self.z_top, merit, np.inf)
        out = {"F": F, "M": M, "t": t, "merit": merit, "g": g}
        if jacobian:
            act = e >= 0.0
            none = ~act.any(axis=1)
            act[none] = True  # no cable taut: Hooke extended to compression (as the point-mass mode)
            tc = np.where(none[:, None], k * e, t)
            Fn = np.einsum("nj,nja->na", tc, g.u) + self.f
            Mn = np.einsum("nj,nja->na", tc, np.cross(r, g.u)) + np.cross(rc, self.f)
            out["Fn"] = np.concatenate(
                [np.where(none[:, None], Fn, F), np.where(none[:, None], Mn, M)], axis=1
            )
            ka = k * act
            dL = length_gradient(g)
            out["J"] = _jacobian(t, direction_gradient(g), ka, g.u, dL, r, rc, self.f)
            out["grad"] = np.concatenate(
                [np.einsum("nj,nja->na", t, dL) - self.f, np.einsum("nj,nja->na", t, np.cross(r, dL))], axis=1
            )
            out["grad"][:, 3:] -= np.cross(rc, self.f)
            stiff = ka + t / g.l_E
            rr = np.einsum("nma,nma->nm", r, r)
            out["kappa"] = np.stack(
                [
                    stiff.sum(axis=1),
                    (stiff * rr + t * np.sqrt(rr)).sum(axis=1)
                    + np.linalg.norm(self.f) * np.linalg.norm(rc, axis=1),
                ],
                axis=1,
            )
        return out


def _jacobian(t, du, ka, u, dL, r, rc, f):
    """d(F, M)/d(dp, dphi) (N, 6, 6) of the force and moment balance (module docstring).

    With G_i = t_i du_i/dB + ka_i u_i dL_i^T and dB_i = dp - [r_i]x dphi:
    dF = sum G_i dB_i; dM = sum [r_i]x G_i dB_i + sum t_i (dphi x r_i) x u_i + (dphi x rc) x f, and
    (dphi x r) x u = (r u^T - (u . r) I) dphi."""
    G = t[..., None, None] * du + ka[..., None, None] * u[..., :, None] * dL[..., None, :]
    Sr = skew(r)
    eye = np.eye(3)
    J = np.zeros(t.shape[:1] + (6, 6))
    J[:, :3, :3] = G.sum(axis=1)
    J[:, :3, 3:] = -np.einsum("nmab,nmbc->nac", G, Sr)
    RG = np.einsum("nmab,nmbc->nmac", Sr, G)
    J[:, 3:, :3] = RG.sum(axis=1)
    turn = t[..., None, None] * (
        r[..., :, None] * u[..., None, :] - np.einsum("nma,nma->nm", u, r)[..., None, None] * eye
    )
    J[:, 3:, 3:] = -np.einsum("nmab,nmbc->nac", RG, Sr) + turn.sum(axis=1)
    J[:, 3:, 3:] += rc[:, :, None] * f[None, None, :] - (rc @ f)[:, None, None] * eye
    return J


def _step(J, Fn, rigid):
    """Newton step s (N, 6) solving J s = -Fn: 3 x 3 (point mass, rotation rows reduced) or the
    least-squares 6 x 6 step."""
    s = np.zeros_like(Fn)
    if not rigid:
        s[:, :3], _ = solve3(J[:, :3, :3], -Fn[:, :3])
        return s
    ok = np.isfinite(J).all(axis=(1, 2))
    s[ok] = np.einsum("nab,nb->na", np.linalg.pinv(J[ok], rcond=RCOND), -Fn[ok])
    s[~ok] = np.nan
    return s


#: Shift of the modified Newton step, relative to the largest eigenvalue of the scaled Hessian.
SHIFT_REL = 1e-6


def _modified_newton(J, grad, ell, fallback):
    """Descent step where the Newton step does not descend the energy: -(H + mu I)^-1 grad with H the
    symmetric part of -dF6/dx in scaled coordinates (rotations times the platform size ``ell``) and
    mu the shift that makes it positive definite (``SHIFT_REL`` of its largest eigenvalue beyond
    the most negative one); the scaled gradient step ``fallback`` where H is not finite."""
    D = np.array([1.0, 1.0, 1.0, ell, ell, ell])
    H = -0.5 * (J + np.swapaxes(J, 1, 2)) / D[:, None] / D[None, :]
    g = grad / D
    ok = np.isfinite(H).all(axis=(1, 2)) & np.isfinite(g).all(axis=1)
    out = fallback.copy()
    if ok.any():
        lam, V = np.linalg.eigh(H[ok])
        top = np.abs(lam).max(axis=1, keepdims=True)
        mu = np.maximum(0.0, -lam[:, :1]) + SHIFT_REL * np.where(top > 0, top, 1.0)
        c = np.einsum("nab,na->nb", V, g[ok]) / (lam + mu)
        out[ok] = -np.einsum("nab,nb->na", V, c) / D
    return out


def _take(state, idx, new, sel):
    for key in ("F", "M", "Fn", "t", "merit", "J", "grad", "kappa"):
        state[key][idx[sel]] = new[key][sel]


def _newton6(cab, p0, R0, L0, p_ref, tol, maxiter, max_step):
    """Line-searched semismooth Newton over N poses; returns p, R, evaluation, iterations, converged."""
    n = p0.shape[0]
    p, R = p0.copy(), R0.copy()
    cur = cab.evaluate(p, R, L0, p_ref)
    cur.pop("g")
    iters = np.zeros(n, dtype=np.int32)
    conv = np.zeros(n, dtype=bool)
    prev = np.zeros(n)
    prev_full = np.zeros(n, dtype=bool)
    active = np.arange(n)
    ell = cab.size if cab.rigid else 0.0
    for _ in range(maxiter):
        F, M = cur["F"][active], cur["M"][active]
        here = (np.einsum("na,na->n", F, F) <= cab.ftol**2) & (
            np.einsum("na,na->n", M, M) <= (cab.ftol * cab.size) ** 2
        )
        conv[active[here]] = True
        active = active[~here]
        if active.size == 0:
            break
        Fn, J, grad, merit, kappa = (cur[k][active] for k in ("Fn", "J", "grad", "merit", "kappa"))
        s = _step(J, Fn, cab.rigid)
        newton = np.isfinite(s).all(axis=1)
        s = np.where(newton[:, None], s, 0.0)
        norm = np.sqrt(
            np.einsum("na,na->n", s[:, :3], s[:, :3]) + ell**2 * np.einsum("na,na->n", s[:, 3:], s[:, 3:])
        )
        slope = np.einsum("na,na->n", grad, s)
        newton &= (slope < 0.0) | (norm <= LS_SKIP)
        kp = np.where(kappa[:, 0] > 0, kappa[:, 0], 1.0)
        kr = np.where(kappa[:, 1] > 0, kappa[:, 1], 1.0)
        fallback = np.concatenate(
            [-grad[:, :3] / kp[:, None], -grad[:, 3:] / kr[:, None] * cab.rigid], axis=1
        )
        if cab.rigid and not newton.all():
            bad = ~newton
            fallback[bad] = _modified_newton(J[bad], grad[bad], cab.size, fallback[bad])
        s = np.where(newton[:, None], s, fallback)
        slope = np.einsum("na,na->n", grad, s)
        norm = np.sqrt(
            np.einsum("na,na->n", s[:, :3], s[:, :3]) + ell**2 * np.einsum("na,na->n", s[:, 3:], s[:, 3:])
        )
        done = newton & ((norm < tol) | (prev_full[active] & (norm * norm < tol * prev[active])))
        scale = np.where(done, 1.0, np.minimum(1.0, max_step / np.maximum(norm, 1e-300)))
        s *= scale[:, None]
        slope *= scale
        whole = done | (norm * scale <= LS_SKIP)

        def trial_at(pending, a):
            idx = active[pending]
            st = a[:, None] * s[pending]
            pt = p[idx] + st[:, :3]
            Rt = rotation_matrix(st[:, 3:]) @ R[idx] if cab.rigid else R[idx]
            return cab.evaluate(pt, Rt, L0[idx], p_ref[idx]), (pt, Rt)

        def accept(pending, trial, state, ok):
            idx = active[pending]
            pt, Rt = state
            p[idx[ok]] = pt[ok]
            R[idx[ok]] = Rt[ok]
            _take(cur, idx, trial, ok)

        alpha = backtrack(trial_at, accept, merit, slope, whole)
        iters[active] += 1
        prev[active] = alpha * norm * scale
        prev_full[active] = newton & (alpha == 1.0) & (scale == 1.0)
        conv[active[done]] = True
        active = active[~done]
    return p, R, cur, iters, conv


def start_poses(robot, p):
    """Newton's starting positions: p, lowered below the lowest anchor for a suspended point-mass
    robot (as ``equilibrium.start_points``); other robots start at p.

    Parameters
    ----------
    robot : Robot
    p : array_like (N, 3) [m]
        Desired positions.

    Returns
    -------
    p0 : ndarray (N, 3) [m]
    """
    p = np.array(p, dtype=float)
    if robot.suspended_point_mass:
        top = robot.A[:, 2].min() - START_BELOW
        p[:, 2] = np.where(p[:, 2] < top, p[:, 2], top)
    return np.ascontiguousarray(p)


def solve_spatial(
    robot, p, rotvec=None, L0=None, P0=None, tol=None, maxiter=None, max_step=None, restarts=True
):
    """Physical equilibrium (p*, R*) of a rigid platform on all m cables, slack cables allowed.

    Parameters
    ----------
    robot : Robot
    p : array_like (N, 3) or (N, 6) [m, rad]
        Desired positions, or poses (x, y, z, rx, ry, rz).
    rotvec : array_like (N, 3) or (3,) [rad], optional
        Desired orientations (rotation vectors, active, base frame), default identity.
    L0 : array_like (N, m) [m], optional
        Commanded rest lengths; default the standard model's L_TS at the desired pose.
    P0 : array_like (N, 3) [m], optional
        Newton's starting positions (default p); the start orientation is the desired one.
    tol, maxiter, max_step : float [m], int, float [m], optional
        As ``equilibrium.PHYSICAL_DEFAULTS``.
    restarts : bool
        Look for other equilibria where the solution may not be unique (module docstring).

    Returns
    -------
    dict
        The keys of ``equilibrium.solve_physical`` (p, P_s, dp, t, taut, n_taut, residual,
        iterations, converged, status_code, status) plus rotvec (N, 3) and rotvec_s (N, 3) [rad],
        R_s (N, 3, 3), dphi (N,) [rad], energy (N,) [J], unique (N,) bool, alternatives (list of
        N lists of dicts with P_s, rotvec_s, energy, taut), wrap_over_270 (N, m) bool.

    References
    ----------
    Paty et al. 2021, eq. (2)-(5), (10)-(14); Pott 2018, ch. 3.
    """
    return solve_with(robot, Cables6(robot), _newton6, p, rotvec, L0, P0, tol, maxiter, max_step, restarts)


def solve_with(robot, cab, newton, p, rotvec, L0, P0, tol, maxiter, max_step, restarts, standard=None):
    """``solve_spatial`` with its Newton iteration given: ``newton(cab, p0, R0, L0, p_ref, tol,
    maxiter, max_step)`` returns (p, R, evaluation dict with at least F, M, t, merit, J, iterations,
    converged) as ``_newton6`` does (the numpy one, or the compiled engine's); ``cab`` a
    ``Cables6`` (or a subclass the given ``newton`` reads); ``standard(robot, p, R)`` the default
    rest lengths (``L_TS_pose`` when None). The pose set-up, the restarts and the result are this
    module's. The evaluation dict may also carry, at the final poses, ``stable`` (N,) (points shown
    positive definite, not checked again by ``_needs_restart``), ``inside``, ``gamma`` (N, m) (the
    pulleys' state) and ``rotvec`` (N, 3), which the result then takes instead of recomputing them.

    Parameters
    ----------
    robot : Robot
    cab : Cables6
    newton : callable
    p, rotvec, L0, P0, tol, maxiter, max_step, restarts
        As ``solve_spatial``.
    standard : callable, optional

    Returns
    -------
    dict
        As ``solve_spatial``.

    References
    ----------
    Paty et al. 2021, eq. (2)-(5), (10)-(14); Pott 2018, ch. 3.
    """
    tol, maxiter, max_step = stop_rules(tol, maxiter, max_step)
    pose = set_up(robot, p, rotvec, L0, P0, standard)
    first = newton(cab, pose.p0, pose.R_d.copy(), pose.L0, pose.p, tol, maxiter, max_step)
    return finish(robot, cab, newton, pose, first, tol, maxiter, max_step, restarts)


class Setup(NamedTuple):
    """The poses of a 6-DoF solve (``set_up``): p (N, 3) [m] desired positions, R_d (N, 3, 3) and
    rv_d (N, 3) [rad] desired orientations, L0 (N, m) [m] rest lengths, p0 (N, 3) [m] the start."""

    p: np.ndarray
    R_d: np.ndarray
    rv_d: np.ndarray
    L0: np.ndarray
    p0: np.ndarray


def stop_rules(tol=None, maxiter=None, max_step=None):
    """Newton's stop rules, ``equilibrium.PHYSICAL_DEFAULTS`` where None.

    Parameters
    ----------
    tol : float [m], optional
    maxiter : int, optional
    max_step : float [m], optional

    Returns
    -------
    tuple
        (tol [m], maxiter, max_step [m]).
    """
    o = PHYSICAL_DEFAULTS
    return (
        o["tol"] if tol is None else tol,
        o["maxiter"] if maxiter is None else maxiter,
        o["max_step"] if max_step is None else max_step,
    )


def set_up(robot, p, rotvec=None, L0=None, P0=None, standard=None):
    """The desired poses, rest lengths and Newton's start of ``solve_with``.

    Parameters
    ----------
    robot : Robot
    p : array_like (N, 3) or (N, 6) [m, rad]
        Desired positions, or poses.
    rotvec : array_like (N, 3) or (3,) [rad], optional
        Desired orientations, default identity.
    L0 : array_like (N, m) [m], optional
        Rest lengths, default ``standard(robot, p, R)``.
    P0 : array_like (N, 3) [m], optional
        Newton's starting positions (default p; ``start_poses``).
    standard : callable, optional
        Default rest lengths, ``L_TS_pose`` when None.

    Returns
    -------
    Setup
    """
    given = np.atleast_2d(np.asarray(p, dtype=float))
    p, R_d = pose_arrays(robot, p, rotvec)
    if given.shape[1] == 6:
        rv_d = given[:, 3:].copy()
    elif rotvec is not None:
        rv_d = np.broadcast_to(np.asarray(rotvec, dtype=float), p.shape).copy()
    else:
        rv_d = np.zeros_like(p)
    n = len(p)
    if L0 is None:
        L0 = (L_TS_pose if standard is None else standard)(robot, p, R_d)
    L0 = np.broadcast_to(np.asarray(L0, dtype=float), (n, robot.m)).copy()
    p0 = start_poses(robot, p if P0 is None else np.atleast_2d(np.asarray(P0, dtype=float)))
    return Setup(p, R_d, rv_d, L0, p0)


def finish(robot, cab, newton, pose, first, tol, maxiter, max_step, restarts):
    """``solve_with`` after its first Newton pass: the restarts (by ``newton``) and the result.

    Parameters
    ----------
    robot : Robot
    cab : Cables6
    newton : callable
        As ``solve_with`` (it solves the restarts).
    pose : Setup
        ``set_up``'s poses.
    first : tuple
        ``newton(cab, pose.p0, pose.R_d, pose.L0, pose.p, tol, maxiter, max_step)``.
    tol, maxiter, max_step : float [m], int, float [m]
        Stop rules (``stop_rules``).
    restarts : bool
        As ``solve_spatial``.

    Returns
    -------
    dict
        As ``solve_spatial``.
    """
    P, R, cur, iters, conv = first
    n = len(pose.p)
    if restarts and cab.rigid and n:
        P, R, cur, iters, conv, unique, alternatives = _restart(
            cab, pose.p, pose.R_d, pose.L0, P, R, cur, iters, conv, tol, maxiter, max_step, newton
        )
    else:
        unique, alternatives = np.ones(n, dtype=bool), [[] for _ in range(n)]
    return _result6(
        robot, cab, pose.p, pose.R_d, pose.rv_d, pose.L0, P, R, cur, iters, conv, unique, alternatives
    )


def solve_spatial_batch(
    robots, p, rotvec=None, L0=None, tol=None, maxiter=None, max_step=None, restarts=True
):
    """``solve_spatial`` of several robots at the same poses and rest lengths (the Monte Carlo and
    Sobol samples of one design): the numpy reference of ``cdpr.compiled.equilibrium6``'s batch,
    which runs every robot's first Newton pass in one parallel pass over (robot, chunk of poses).

    Parameters
    ----------
    robots : sequence of Robot
        Robots with the same number of cables m.
    p : array_like (N, 3) or (N, 6) [m, rad]
        Desired positions, or poses.
    rotvec : array_like (N, 3) or (3,) [rad], optional
    L0 : array_like (N, m) [m], optional
        Commanded rest lengths of every robot; default L_TS at the desired pose of each robot.
    tol, maxiter, max_step, restarts
        As ``solve_spatial``.

    Returns
    -------
    list of dict
        ``solve_spatial`` of each robot.
    """
    return [solve_spatial(r, p, rotvec, L0, None, tol, maxiter, max_step, restarts) for r in robots]


def _needs_restart(cab, cur, conv):
    """Points whose equilibrium may not be unique: fewer than 6 taut cables, or a converged
    Hessian -dF6/dx (symmetric part) that is not positive definite."""
    n_taut = (cur["t"] > TAUT_MIN).sum(axis=1)
    # the points a solver has shown positive definite (the compiled engine's Cholesky) are not redone
    todo = ~cur["stable"] if "stable" in cur else np.ones(len(conv), dtype=bool)
    lam = np.full(len(conv), np.inf)
    J = cur["J"][todo]
    H = -0.5 * (J + np.swapaxes(J, 1, 2))
    ok = np.isfinite(H).all(axis=(1, 2))
    lam_todo = np.full(len(H), -np.inf)
    lam_todo[ok] = np.linalg.eigvalsh(H[ok])[:, 0]
    lam[todo] = lam_todo
    return (n_taut < 6) | ~(lam > 0) | ~conv


def _restart(cab, p, R_d, L0, P, R, cur, iters, conv, tol, maxiter, max_step, newton=None):
    """The points of ``_needs_restart`` solved again from ``RESTARTS`` by ``newton`` (default
    ``_newton6``): the lowest-energy equilibrium, ``unique`` and the ``alternatives`` (module
    docstring)."""
    newton = _newton6 if newton is None else newton
    n = len(p)
    unique = np.ones(n, dtype=bool)
    alternatives = [[] for _ in range(n)]
    idx = np.flatnonzero(_needs_restart(cab, cur, conv))
    if idx.size == 0:
        return P, R, cur, iters, conv, unique, alternatives
    k = len(RESTARTS)
    rep = np.repeat(idx, k)
    Rs = rotation_matrix(np.tile(RESTARTS, (idx.size, 1))) @ R_d[rep]
    P2, R2, cur2, it2, conv2 = newton(
        cab, start_poses(cab.robot, p[rep]), Rs, L0[rep], p[rep], tol, maxiter, max_step
    )
    f, K = idx.size, k + 1
    cP = np.concatenate([P[idx][:, None], P2.reshape(f, k, 3)], axis=1)  # candidates (f, K, ...)
    cR = np.concatenate([R[idx][:, None], R2.reshape(f, k, 3, 3)], axis=1)
    cE = np.concatenate([cur["merit"][idx][:, None], cur2["merit"].reshape(f, k)], axis=1)
    cT = np.concatenate([cur["t"][idx][:, None], cur2["t"].reshape(f, k, -1)], axis=1)
    valid = np.concatenate([conv[idx][:, None], conv2.reshape(f, k)], axis=1) & np.isfinite(cE)
    valid[:, 0] |= ~valid.any(axis=1)  # nothing converged: keep the first solve
    order = np.argsort(np.where(valid, cE, np.inf), axis=1, kind="stable")
    sP = np.take_along_axis(cP, order[..., None], axis=1)
    sR = np.take_along_axis(cR, order[..., None, None], axis=1)
    sV = np.take_along_axis(valid, order, axis=1)
    same = (np.linalg.norm(sP[:, :, None] - sP[:, None, :], axis=-1) <= DISTINCT) & (
        rotation_error(sR[:, :, None], sR[:, None, :]) <= DISTINCT
    )
    distinct = np.zeros((f, K), dtype=bool)
    distinct[:, 0] = True
    for c in range(1, K):  # over the K candidates, vectorised over the points
        distinct[:, c] = sV[:, c] & ~(same[:, c, :c] & distinct[:, :c]).any(axis=1)
    best = order[:, 0]
    moved = best > 0
    src = np.arange(f)[moved] * k + best[moved] - 1
    dst = idx[moved]
    P[dst], R[dst], conv[dst] = P2[src], R2[src], conv2[src]
    iters[dst] += it2[src]
    for key in cur:
        cur[key][dst] = cur2[key][src]
    unique[idx] = distinct.sum(axis=1) == 1
    sE = np.take_along_axis(cE, order, axis=1)
    sT = np.take_along_axis(cT, order[..., None], axis=1)
    rv = rotvec_of(sR)
    for a in np.flatnonzero(~unique[idx]):  # the JSON list of the other equilibria (output only)
        alternatives[idx[a]] = [
            {
                "P_s": sP[a, c].tolist(),
                "rotvec_s": rv[a, c].tolist(),
                "energy": float(sE[a, c]),
                "taut": (np.flatnonzero(sT[a, c] > TAUT_MIN) + 1).tolist(),
            }
            for c in np.flatnonzero(distinct[a])[1:]
        ]
    return P, R, cur, iters, conv, unique, alternatives


def _result6(robot, cab, p, R_d, rv_d, L0, P, R, cur, iters, conv, unique, alternatives):
    t = cur["t"]
    taut = t > TAUT_MIN
    if "inside" in cur:  # the solver gave the pulleys' state at (P, R) (the compiled engine)
        inside, gamma = cur["inside"], cur["gamma"]
    else:
        _, st = pose_state(robot, P, R)
        inside, gamma = st.inside, st.gamma
    if robot.suspended_point_mass:
        code = statuses(robot, p, P, t, conv, inside, hull_halfplanes(robot))
    else:
        finite = np.isfinite(P).all(axis=1) & np.isfinite(R).all(axis=(1, 2))
        code = np.full(len(p), ST["ok"], dtype=np.int8)
        code[(t > robot.T_a).any(axis=1)] = ST["over_tension"]
        code[~finite | inside.any(axis=1)] = ST["inaccessible"]
        code[~conv | ~taut.any(axis=1)] = ST["not_converged"]
    residual = np.sqrt(np.einsum("na,na->n", cur["F"], cur["F"]) + np.einsum("na,na->n", cur["M"], cur["M"]))
    if cab.rigid:
        rv_s = cur["rotvec"] if "rotvec" in cur else rotvec_of(R)
    else:
        rv_s = rv_d.copy()
    R_s = R if cab.rigid else R_d
    return {
        "p": p,
        "P_s": P,
        "dp": np.linalg.norm(P - p, axis=1),
        "rotvec": rv_d,
        "rotvec_s": rv_s,
        "R_s": R_s,
        "dphi": rotation_error(R_s, R_d) if cab.rigid else np.zeros(len(p)),
        "t": np.where(taut, t, np.nan),
        "taut": taut,
        "n_taut": taut.sum(axis=1).astype(np.int8),
        "residual": residual,
        "iterations": iters,
        "converged": conv,
        "status_code": code,
        "status": np.asarray(STATUSES)[code],
        "energy": cur["merit"],
        "unique": unique,
        "alternatives": alternatives,
        "wrap_over_270": gamma > 1.5 * np.pi,
        "L0": L0,
    }
