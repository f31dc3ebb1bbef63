"""Physical equilibrium ("redundancy: physical") of a platform on m elastic cables with pulleys at
any orientation: the rigid 6-DoF platform, and the point mass as its case b_i = 0, c = 0.

The winches hold commanded rest lengths L0_i (by default the standard model's L_TS,i at the desired
pose, as in the paper, eq. 2). The platform settles at the pose (p*, R*) where

    W(p*, R*) t + w_ext(R*) = 0,   t_i = (E_i S_i / L0_i) max(0, L_TE,i(B_i) - L0_i),   B_i = p + R b_i

(Hooke, eq. 10 and 13, with a cable that cannot push: a cable shorter than its rest length is slack,
t_i = 0), with W the 6 x m wrench matrix (``platform.wrench_matrix``; column [u_i ; r_i x u_i],
r_i = R b_i, u_i from B_i toward the exit point D_i of the pulley,
``pulleys.total_length_and_direction`` at B_i; L_TE,i the extended total length, eq. 3-5, 12) and
w_ext the gravity wrench at the centre of mass plus an external wrench beside gravity
(``Platform.wrench``: a constant world-frame force at p and moment about p; on a point mass the
force joins the weight, ``Platform.w_ext``) (``platform.external_wrench``). Every cable may go
slack: nothing chooses which cables hold the platform, unlike the paper's 3-cable subsets. On a
point mass (b_i = 0, c = 0) the rotation plays no part and the moment rows vanish: the solver works
on the 3 force rows (rank(W) = 3), F(P*) = sum_i t_i u_i(P*) + w_ext = 0.

Solver
------
Semismooth Newton on the force and moment balance F6 with its analytic generalised Jacobian in
the pose increments x = (dp, dphi) (dphi a base-frame rotation vector, R <- exp([dphi]x) R):
dB_i = dp - [r_i]x dphi, and with G_i = t_i du_i/dB + (E_i S_i / L0_i) a_i u_i (dL_i/dB)^T,
a_i = [L_TE,i >= L0_i] (``statics.direction_gradient``, ``statics.length_gradient``),

    dF/dx = sum_i G_i [I, -[r_i]x]
    dM/dx = sum_i [r_i]x G_i [I, -[r_i]x] + [0, sum_i t_i (r_i u_i^T - (u_i . r_i) I)]  (``_jacobian``)

The step is the least-squares (pseudo-inverse) Newton step of the 6 x 6 system (a neutral mode,
such as the rotation of a platform hanging from one point about the vertical, gets no step), the
3 x 3 solve on a point mass; steps are capped at ``max_step`` and globalised by an Armijo
backtracking line search (``backtrack``) on the potential energy

    V = sum_i E_i S_i / (2 L0_i) max(0, L_TE,i - L0_i)^2 - w_ext . (p - p_d + R c)

with its exact gradient dV/dx. An external force F_e at p adds -F_e . (p - p_d) to V; a constant
world-frame moment M_e has no potential (its work over a rotation depends on the path), so the
gradient takes -M_e in its rotation rows and each trial step x + a s of the line search adds the
moment's work a M_e . s_phi to V (exact: the base-frame angular displacement of exp([a s_phi]x) R
is a s_phi), and the merit kept (``energy``, the restarts' "lowest energy") leaves the moment out.

* Fixed and SR pulleys: dL_TE/dB = -u, so dV/dx = -F6 exactly: the equilibrium is the minimum of
  V. On a point mass V is convex for fixed pulleys and its Hessian -dF/dP is positive definite as
  soon as one cable pulls, so the Newton direction descends V and the minimum is unique.
* DR pulleys: with our reading of the DR arm (on the bisector of the strand toward B and the
  strand toward the winch, ``pulleys.sheave_centre``) dL_TE/dB has an arm term, and dV/dB = -F +
  sum_i t_i arm_i ((u_i + u_C,i) . beta_i) eps_i; on CDPR4_DR equilibria the difference is 5e-7 to
  9e-4 of M g (median 1.5e-5), and the minimum of V lies up to 2e-5 m (median 2e-7 m) from the
  force balance. The force balance is the definition of the equilibrium, so Newton solves F6 = 0
  and V serves only as the merit of the line search far from the solution: Newton steps shorter
  than ``LS_SKIP`` = 0.1 mm are taken whole, without the descent test or the line search.
  Convergence is judged on F6 only.

Where the Newton direction does not descend V (an indefinite Hessian from the swivel term next to
the vertical through a joint point, a singular Jacobian) the step is the scaled gradient step
-dV/dx / kappa (kappa a bound of the stiffness), on a rigid platform the modified Newton step
(``_modified_newton``). When no cable is taut (with L0 = L_TS every DR cable is slack at p by 1-4
cm) the Newton step takes every cable as taut, Hooke extended to compression: one step then lowers
the platform to about where the cables hold it. On a suspended point-mass robot, trial points at or
above the lowest joint point have infinite merit (rejected) and a start there is moved below it
(``start_points``).

A point converges when |F| <= ``FTOL_REL`` |w_ext| and |M| <= ``FTOL_REL`` |w_ext| l (l the
platform's size) where it stands, or when a Newton step s_k is shorter than ``tol``, or when the
error left after it, estimated from the contraction as |s_k|^2 / |s_(k-1)| after a full Newton
step s_(k-1), is below ``tol`` (``direct._newton``'s rule).

Several equilibria: a robot with slack cables can hang in more than one pose. Where the converged
Hessian -dF6/dx is not positive definite or fewer than 6 cables are taut (rigid platforms only),
the point is solved again from ``RESTARTS`` (the desired pose turned by +-``RESTART_ANGLE`` about
x, y, z); the lowest-energy equilibrium found is returned, ``unique`` is False where another one
(more than ``DISTINCT`` apart) exists, and the others are listed under ``alternatives``. A heavy
cable always pulls, so for this rule it counts as taut only while its sag leaves it at least
``SLACK_STIFFNESS`` of its elastic stiffness (``hanging_cables``: Ernst's equivalent modulus); one
that hangs with about its own weight holds the platform no more than a slack massless cable does.

Edge cases (choices)
--------------------
* Fewer taut cables than degrees of freedom is physical (a point mass hangs as a pendulum on 2
  cables in the vertical plane through their exit points, or on one cable under its pulley): status
  ``ok`` when converged; ``taut`` says which cables hold it.
* ``slack`` (a status of paper mode) never occurs: slackness is part of the model.
* ``inaccessible`` on a suspended point-mass robot (``results.statuses``): the desired point or
  the equilibrium lies at or above the lowest joint point, or outside the anchors' horizontal
  convex hull (where gravity cannot be balanced by pulling cables, up to the pulley offsets), or the
  equilibrium lies inside a sheave, or is not finite. On every other robot a pose is inaccessible
  only when the equilibrium is not finite or lies inside a sheave. P* is still reported.
* ``over_tension``: converged, accessible, and some t_i > T_a,i.
* ``not_converged``: the iteration cap was reached (the pose and tensions where Newton stopped),
  or Newton stopped with every cable slack (a free platform has no equilibrium).
* The floor is not modelled (as in paper mode): P* may lie below z = 0.
* Tensions: exactly 0 on slack cables in the model; the result writes NaN there, with the boolean
  ``taut`` beside (t_i > ``results.TAUT_MIN`` = 1e-6 N).
* A lone SR or DR cable holding a point mass has a circle of equilibria round its joint axis (the
  swivel is neutral), so P* there depends on the starting point and on round-off; |F(P*)| is still
  balanced.

The compiled engine (``cdpr.compiled.equilibrium``) solves the same equations; a suspended point
mass takes its 3-DoF kernel there (the same Newton with 3 x 3 solves), tested equal to this
reference to 1e-9 m.

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

from cdpr.errors import CdprError
from cdpr.models.cables import Cables, HeavyCables, heavy_cables
from cdpr.models.inverse import L_TS, pose_state
from cdpr.models.platform import pose_arrays, rotation_error, rotation_matrix, rotvec_of
from cdpr.models.results import ST, STATUSES, TAUT_MIN, hull_halfplanes, statuses
from cdpr.models.statics import solve3

#: Newton defaults: position tolerance [m], iteration cap, largest step [m].
PHYSICAL_DEFAULTS = {"tol": 1e-10, "maxiter": 60, "max_step": 0.5}
#: Armijo constant of the backtracking line search and its largest number of halvings.
ARMIJO_C = 1e-4
MAX_HALVINGS = 30
#: Steps shorter than this [m] are taken whole, without the line search.
LS_SKIP = 1e-4
#: A start at or above the lowest joint point is moved to this distance [m] below it.
START_BELOW = 0.05
#: Restart orientations: the desired one turned by +-RESTART_ANGLE [rad] about x, y and z.
RESTART_ANGLE = np.radians(20.0)
RESTARTS = np.array([[s * RESTART_ANGLE * (i == a) for i in range(3)] for a in range(3) for s in (1, -1)])
#: Two equilibria are distinct when their poses differ by more than this [m] or [rad].
DISTINCT = 1e-6
#: A heavy cable whose equivalent modulus (Ernst) is below this share of E counts as slack for the
#: restart rule (``hanging_cables``).
SLACK_STIFFNESS = 0.01
#: Relative singular-value cut of the least-squares Newton step.
RCOND = 1e-12


def backtrack(trial_at, accept, merit, slope, whole):
    """Armijo backtracking line search over a batch of Newton steps (Nocedal & Wright 2006, alg. 3.1),
    of the equilibrium's Newton iteration (``_newton`` here, and the compiled engines'): the step fraction
    α_k = 2^-h of point k is accepted at the first h with

        V(x_k + α_k s_k) <= V(x_k) + c α_k ∇V·s_k,   c = ARMIJO_C,

    or at once where ``whole`` (a converged or negligible step), or at h = MAX_HALVINGS.

    Parameters
    ----------
    trial_at : callable (pending (n,) int, alpha (n,)) -> (trial dict with "merit" (n,), state)
        Evaluates the trial points x_k + α_k s_k of the still pending points.
    accept : callable (pending, trial, state, ok (n,) bool) -> None
        Commits the accepted trials.
    merit, slope : ndarray (K,)
        V(x_k) and the directional derivative ∇V·s_k (negative along a descent step).
    whole : ndarray (K,) bool
        Points whose full step is taken without a test.

    Returns
    -------
    alpha : ndarray (K,)
        The accepted step fractions.

    References
    ----------
    Nocedal, J., Wright, S. J. (2006). Numerical Optimization, 2nd ed. Springer, ch. 3.1.
    """
    alpha = np.ones(len(merit))
    pending = np.arange(len(merit))
    for h in range(MAX_HALVINGS + 1):
        trial, state = trial_at(pending, alpha[pending])
        ok = (
            whole[pending]
            | (trial["merit"] <= merit[pending] + ARMIJO_C * alpha[pending] * slope[pending])
            | (h == MAX_HALVINGS)
        )
        accept(pending, trial, state, ok)
        pending = pending[~ok]
        if pending.size == 0:
            break
        alpha[pending] *= 0.5
    return alpha


def start_points(robot, P0):
    """Newton's starting points: P0 (N, 3) [m]; on a suspended point-mass robot moved down to
    ``START_BELOW`` under the lowest joint point where it lies higher than that (the model means
    nothing above the pulleys; this happens for a desired point above them, reported
    inaccessible). Other robots start at P0.

    Parameters
    ----------
    robot : Robot
        Supplies the joint points A (m, 3) [m].
    P0 : array_like (N, 3) or (3,) [m]
        Starting points.

    Returns
    -------
    P0 : ndarray (N, 3) [m]
        A C-contiguous copy; on a suspended point-mass robot z lowered to (lowest joint height -
        ``START_BELOW``) where it was above that level.
    """
    P0 = np.array(np.atleast_2d(np.asarray(P0, dtype=float)))
    if robot.suspended_point_mass:
        top = robot.A[:, 2].min() - START_BELOW
        P0[:, 2] = np.where(P0[:, 2] < top, P0[:, 2], top)
    return np.ascontiguousarray(P0)


def batch_starts(robots, p, P0=None):
    """The starting points of every robot of a batched solve.

    Parameters
    ----------
    robots : sequence of Robot
        K robots.
    p : array_like, shape (N, 3) [m]
        Desired positions.
    P0 : array_like, shape (N, 3) or (K, N, 3) [m], optional
        One start for every robot, or robot k's in ``P0[k]``; default p.

    Returns
    -------
    list of ndarray, shape (N, 3) [m]
        ``start_points`` of robot k at its start.
    """
    p = np.atleast_2d(np.asarray(p, dtype=float))
    if P0 is None:
        return [start_points(r, p) for r in robots]
    P0 = np.asarray(P0, dtype=float)
    if P0.shape not in ((len(p), 3), (len(robots), len(p), 3)):
        raise CdprError(
            f"P0 has shape {P0.shape}; allowed: (N, 3) or (K, N, 3) = ({len(robots)}, {len(p)}, 3)"
        )
    if P0.ndim == 2:
        P0 = np.broadcast_to(P0, (len(robots), *P0.shape))
    return [start_points(r, P) for r, P in zip(robots, P0)]


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


def _newton(cab, p0, R0, L0, p_ref, tol, maxiter, max_step):
    """Line-searched semismooth Newton over N poses; returns p, R, evaluation, iterations, converged."""
    n = p0.shape[0]
    p, R = p0.copy(), R0.copy()
    heavy = isinstance(cab, HeavyCables)
    # heavy cables: the exact Jacobian at the trials of whole steps (near the answer), the cheaper
    # one before (``HeavyCables.evaluate``'s ``exact``; the compiled engine's rule)
    cur = cab.evaluate(p, R, L0, p_ref, exact=False) if heavy else cab.evaluate(p, R, L0, p_ref)
    cur.pop("g")
    iters = np.zeros(n, dtype=np.int32)
    conv = np.zeros(n, dtype=bool)
    prev = np.zeros(n)
    prev_full = np.zeros(n, dtype=bool)
    active = np.arange(n)
    ell = cab.size if cab.rigid else 0.0
    moment = cab.rigid and bool(np.any(getattr(cab, "me", 0.0)))
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
            if heavy:
                trial = cab.evaluate(pt, Rt, L0[idx], p_ref[idx], exact=whole[pending])
            else:
                trial = cab.evaluate(pt, Rt, L0[idx], p_ref[idx])
            # an external moment's work along the trial step (R_t = exp([st]x) R: the base-frame
            # angular displacement is st exactly), so that the merit's change matches the slope
            potential = None
            if moment:
                potential = trial["merit"]
                trial["merit"] = potential - st[:, 3:] @ cab.me
            return trial, (pt, Rt, potential)

        def accept(pending, trial, state, ok):
            idx = active[pending]
            pt, Rt, potential = state
            if potential is not None:  # the merit kept is the potential (no path work)
                trial["merit"] = potential
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


def local_newton(cab, p0, R0, L0, p_ref, tol, maxiter, max_step):
    """The local solver of the equilibrium, no restarts: the line-searched semismooth Newton
    iteration of this module (its docstring gives the equations) from given poses, as the
    continuation of the reached equilibrium (``continuation``) steps it.

    Parameters
    ----------
    cab : Cables
    p0 : ndarray (N, 3) [m]
        Start positions.
    R0 : ndarray (N, 3, 3) [-]
        Start orientations (not modified).
    L0 : ndarray (N, m) [m]
        Rest lengths.
    p_ref : ndarray (N, 3) [m]
        The energy's origin (the desired positions).
    tol, maxiter, max_step : float [m], int, float [m]
        Stop rules (``stop_rules``).

    Returns
    -------
    p : ndarray (N, 3) [m]
    R : ndarray (N, 3, 3) [-]
    cur : dict
        F, M (N, 3) [N, N m], t (N, m) [N], merit (N,) [J], J (N, 6, 6) at the last pose.
    iters : ndarray (N,) int32
    conv : ndarray (N,) bool
    """
    return _newton(
        cab, np.asarray(p0, dtype=float), np.array(R0, dtype=float), L0, p_ref, tol, maxiter, max_step
    )


def solve(
    robot, p, rotvec=None, L0=None, P0=None, tol=None, maxiter=None, max_step=None, restarts=True, heavy=None
):
    """Physical equilibrium (p*, R*) of the platform on all m cables, slack cables allowed (a point
    mass: P* with the desired orientation carried through).

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
    heavy : bool, optional
        Model the cables as heavy (``HeavyCables``: Irvine's elastic catenary, fixed pulleys only so
        far); default ``robot.heavy`` (a linear density > 0). True with a massless robot runs the
        massless model through the catenary (w = 0).

    Returns
    -------
    dict
        p (N, 3) [m]; P_s (N, 3) [m] the equilibrium p*; dp (N,) [m] = |p* - p| (Paty 2021
        eq. 14); t (N, m) [N], NaN on slack cables; taut (N, m) bool (t_i > ``TAUT_MIN``);
        n_taut (N,); residual (N,) [N] = |(F, M)|; iterations (N,); converged (N,) bool;
        status_code (N,) int8 and status (N,) str of ``results.STATUSES``; rotvec (N, 3) and
        rotvec_s (N, 3) [rad],
        R_s (N, 3, 3), dphi (N,) [rad], energy (N,) [J], unique (N,) bool, alternatives (list of
        N lists of dicts with P_s, rotvec_s, energy, taut), wrap_over_270 (N, m) bool.

    References
    ----------
    Paty et al. 2021, eq. (2)-(5), (10)-(14); Pott 2018, ch. 3.
    """
    heavy = robot.heavy if heavy is None else heavy
    cab = HeavyCables(robot) if heavy else Cables(robot)
    res = solve_with(robot, cab, _newton, p, rotvec, L0, P0, tol, maxiter, max_step, restarts)
    if heavy:
        res.update(heavy_cables(cab, res["P_s"], res["R_s"], res["L0"]))
    return res


def solve_with(robot, cab, newton, p, rotvec, L0, P0, tol, maxiter, max_step, restarts, standard=None):
    """``solve`` with its Newton iteration given: ``newton(cab, p0, R0, L0, p_ref, tol,
    maxiter, max_step)`` returns (p, R, evaluation dict with at least F, M, t, merit, J, iterations,
    converged) as ``_newton`` does (the numpy one, or the compiled engine's); ``cab`` a
    ``Cables`` (or a subclass the given ``newton`` reads); ``standard(robot, p, R)`` the default
    rest lengths (``L_TS`` when None). The pose set-up, the restarts and the result are this
    module's. The evaluation dict may also carry, at the final poses, ``stable`` (N,) (points shown
    positive definite, not checked again by ``_needs_restart``), ``inside``, ``gamma`` (N, m) (the
    pulleys' state) and ``rotvec`` (N, 3), which the result then takes instead of recomputing them.

    Parameters
    ----------
    robot : Robot
    cab : Cables
    newton : callable
    p, rotvec, L0, P0, tol, maxiter, max_step, restarts
        As ``solve``.
    standard : callable, optional

    Returns
    -------
    dict
        As ``solve``.

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
        Newton's starting positions (default p; ``start_points``).
    standard : callable, optional
        Default rest lengths, ``L_TS`` when None.

    Returns
    -------
    Setup
    """
    given = np.atleast_2d(np.asarray(p, dtype=float))
    p, R_d = pose_arrays(p, rotvec)
    if given.shape[1] == 6:
        rv_d = given[:, 3:].copy()
    elif rotvec is not None:
        rv_d = np.broadcast_to(np.asarray(rotvec, dtype=float), p.shape).copy()
    else:
        rv_d = np.zeros_like(p)
    n = len(p)
    if L0 is None:
        L0 = L_TS(robot, p, R=R_d) if standard is None else standard(robot, p, R_d)
    L0 = np.broadcast_to(np.asarray(L0, dtype=float), (n, robot.m)).copy()
    p0 = start_points(robot, p if P0 is None else np.atleast_2d(np.asarray(P0, dtype=float)))
    return Setup(p, R_d, rv_d, L0, p0)


def finish(robot, cab, newton, pose, first, tol, maxiter, max_step, restarts):
    """``solve_with`` after its first Newton pass: the restarts (by ``newton``) and the result.

    Parameters
    ----------
    robot : Robot
    cab : Cables
    newton : callable
        As ``solve_with`` (it solves the restarts).
    pose : Setup
        ``set_up``'s poses.
    first : tuple
        ``newton(cab, pose.p0, pose.R_d, pose.L0, pose.p, tol, maxiter, max_step)``.
    tol, maxiter, max_step : float [m], int, float [m]
        Stop rules (``stop_rules``).
    restarts : bool
        As ``solve``.

    Returns
    -------
    dict
        As ``solve``.
    """
    P, R, cur, iters, conv = first
    n = len(pose.p)
    if restarts and cab.rigid and n:
        P, R, cur, iters, conv, unique, alternatives = _restart(
            cab, pose.p, pose.R_d, pose.L0, P, R, cur, iters, conv, tol, maxiter, max_step, newton
        )
    else:
        unique, alternatives = np.ones(n, dtype=bool), [[] for _ in range(n)]
    return _result(
        robot, cab, pose.p, pose.R_d, pose.rv_d, pose.L0, P, R, cur, iters, conv, unique, alternatives
    )


def solve_batch(
    robots, p, rotvec=None, L0=None, tol=None, maxiter=None, max_step=None, restarts=True, P0=None
):
    """``solve`` of several robots at the same poses and rest lengths (the Monte Carlo and
    Sobol samples of one design): the numpy reference of ``cdpr.compiled.equilibrium``'s batch,
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
        As ``solve``.
    P0 : array_like (N, 3) or (K, N, 3) [m], optional
        Newton's starting positions: the same for every robot, or robot k's in ``P0[k]`` (a warm
        start near each robot's equilibrium); default p.

    Returns
    -------
    list of dict
        ``solve`` of each robot.
    """
    robots = list(robots)
    starts = [None] * len(robots) if P0 is None else batch_starts(robots, pose_arrays(p)[0], P0)
    return [solve(r, p, rotvec, L0, P, tol, maxiter, max_step, restarts) for r, P in zip(robots, starts)]


def hanging_cables(t, w, EA, L0):
    """Heavy cables that hang rather than hold: Ernst's equivalent modulus of a sagging cable,

    .. math:: E_{eq} = \\frac{E}{1 + \\frac{(w \\ell)^2 E A}{12 T^3}},

    below ``SLACK_STIFFNESS`` E, i.e. (w ℓ)² EA / (12 T³) > 1 / SLACK_STIFFNESS − 1, with ℓ the
    cable's whole rest length L0 (an upper bound of its free span, so the test errs towards
    "hanging"). For CoGiRo's 4 mm cable (w ℓ ≈ 10 N, EA = 1.28 MN) the threshold is about 47 N.

    Parameters
    ----------
    t : ndarray, shape (N, m) [N]
        Tensions at B.
    w : ndarray, shape (m,) [N/m]
        Weights per unstrained metre (0: massless, never hanging).
    EA : ndarray, shape (m,) [N]
        Axial stiffnesses.
    L0 : ndarray, shape (N, m) [m]
        Rest lengths.

    Returns
    -------
    ndarray, shape (N, m) of bool

    References
    ----------
    Ernst, H. J. (1965). Der E-Modul von Seilen unter Berücksichtigung des Durchhanges. Der
    Bauingenieur 40(2), 52-55; Irvine 1981, ch. 2.
    """
    wl = w * L0
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = wl**2 * EA / (12.0 * np.asarray(t, dtype=float) ** 3)
    return (w > 0) & ~(ratio <= 1.0 / SLACK_STIFFNESS - 1.0)


def _needs_restart(cab, cur, conv, L0=None):
    """Points whose equilibrium may not be unique: fewer than 6 taut cables (heavy cables that hang,
    ``hanging_cables``, do not count), or a converged Hessian -dF6/dx (symmetric part) that is not
    positive definite."""
    taut = cur["t"] > TAUT_MIN
    w = getattr(cab, "w", None)
    if w is not None and L0 is not None and np.any(w > 0):
        taut &= ~hanging_cables(cur["t"], w, cab.EA, L0)
    n_taut = taut.sum(axis=1)
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
    ``_newton``): the lowest-energy equilibrium, ``unique`` and the ``alternatives`` (module
    docstring)."""
    newton = _newton if newton is None else newton
    n = len(p)
    unique = np.ones(n, dtype=bool)
    alternatives = [[] for _ in range(n)]
    idx = np.flatnonzero(_needs_restart(cab, cur, conv, L0))
    if idx.size == 0:
        return P, R, cur, iters, conv, unique, alternatives
    k = len(RESTARTS)
    rep = np.repeat(idx, k)
    Rs = rotation_matrix(np.tile(RESTARTS, (idx.size, 1))) @ R_d[rep]
    P2, R2, cur2, it2, conv2 = newton(
        cab, start_points(cab.robot, p[rep]), Rs, L0[rep], p[rep], tol, maxiter, max_step
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


def _result(robot, cab, p, R_d, rv_d, L0, P, R, cur, iters, conv, unique, alternatives):
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
