"""Physical equilibrium of a point-mass platform on m >= 3 elastic cables ("redundancy: physical").

The winches hold commanded rest lengths L0_i (by default the standard model's L_TS,i at the
desired point p, as in the paper, eq. 2). The platform settles at P* where the cable forces balance
the external wrench,

    F(P*) = sum_i t_i(P*) u_i(P*) + w_ext = 0,    t_i = (E_i S_i / L0_i) max(0, L_TE,i(P*) - L0_i)

(Hooke, eq. 10 and 13, with a cable that cannot push: a cable shorter than its rest length is slack,
t_i = 0). u_i is the unit vector from P toward the exit point D_i of cable i and L_TE,i its total
length in the extended model (eq. 3-5, 12). Every cable may go slack: nothing chooses which cables
hold the platform, unlike the paper's 3-cable subsets (``redundancy``).

Solver
------
Semismooth Newton on the force balance F with the analytic (generalised) Jacobian

    dF/dP = sum_i [t_i du_i/dP + (E_i S_i / L0_i) a_i u_i (dL_TE,i/dP)^T],   a_i = [L_TE,i >= L0_i]

(``statics.direction_gradient`` and ``statics.length_gradient``), steps capped at ``max_step``,
globalised by an Armijo backtracking line search on the potential energy

    V(P) = -w_ext . (P - p) + sum_i E_i S_i / (2 L0_i) max(0, L_TE,i(P) - L0_i)^2

with its exact gradient dV/dP = -w_ext + sum_i t_i dL_TE,i/dP.

* Fixed and SR pulleys: dL_TE/dP = -u, so dV/dP = -F exactly: the equilibrium is the minimum of V.
  V is convex for fixed pulleys and its Hessian -dF/dP is positive definite as soon as one cable
  pulls, so the Newton direction descends V and the minimum is unique (tested from several starts).
* DR pulleys: with our reading of the DR arm (on the bisector of the strand toward P and the
  strand toward the winch, ``pulleys.sheave_centre``) dL_TE/dP has an arm term, and
  dV/dP = -F + sum_i t_i arm_i ((u_i + u_C,i) . beta_i) eps_i; on CDPR4_DR equilibria the
  difference is 5e-7 to 9e-4 of M g (median 1.5e-5), and the minimum of V lies up to 2e-5 m
  (median 2e-7 m) from the force balance. The force balance is the definition of the equilibrium,
  so Newton solves F = 0 and V serves only as the merit of the line search far from the solution:
  Newton steps shorter than ``LS_SKIP`` = 0.1 mm are taken whole, without the descent test or the
  line search (this is also where V's differences would sink into round-off for any pulley).
  Convergence is judged on F only.

Where the Newton direction does not descend V (an indefinite Hessian from the swivel term next to
the vertical through a joint point, a singular Jacobian) the step is -dV/dP / kappa,
kappa = sum_i a_i E_i S_i / L0_i + sum_i t_i / |l_E,i| (a bound of the stiffness). When no cable
is taut (with L0 = L_TS every DR cable is slack at p by 1-4 cm) the Newton step takes every cable
as taut, Hooke extended to compression (t_i = k_i e_i < 0 allowed in Newton's force and Jacobian):
one step then lowers the platform to about where the cables hold it. Trial points at or above the
lowest joint point have infinite merit (rejected); a start there is moved below it
(``start_points``).

A point converges when |F| <= ``FTOL_REL`` |w_ext| where it stands, or when a Newton step s_k is
shorter than ``tol``, or when the error left after it, estimated from the contraction as
|s_k|^2 / |s_(k-1)| after a full Newton step s_(k-1), is below ``tol`` (``direct._newton``'s rule);
that step is taken and the cables are evaluated there.

Edge cases (choices)
--------------------
* Fewer than 3 taut cables is physical (the platform hangs as a pendulum on 2 cables in the
  vertical plane through their exit points, or on one cable under its pulley): status ``ok`` when
  converged; ``taut`` says which cables hold it.
* ``slack`` (a status of paper mode) never occurs: slackness is part of the model.
* ``inaccessible``: the desired point or the equilibrium lies at or above the lowest joint point, or
  outside the anchors' horizontal convex hull (where gravity cannot be balanced by pulling cables,
  up to the pulley offsets), or the equilibrium lies inside a sheave, or is not finite. P* is still
  reported.
* ``over_tension``: converged, accessible, and some t_i > T_a,i.
* ``not_converged``: the iteration cap was reached (P* and tensions where Newton stopped), or
  Newton stopped with every cable slack (a free platform has no equilibrium; this happens only when
  the cables are so stiff that the stretch needed is below the round-off of P).
* The floor is not modelled (as in paper mode): P* may lie below z = 0.
* Tensions: exactly 0 on slack cables in the model; the result writes NaN there (like paper mode's
  slack cables, written null in JSON), with the boolean ``taut`` beside. A cable is taut when
  t_i > ``TAUT_MIN`` = 1e-6 N (below, the tension is the round-off of a cable resting at exactly its
  rest length, which happens where the platform hangs on a lone cable, see below).
* A lone SR or DR cable holding the platform has a circle of equilibria round its joint axis (the
  swivel, or the U-joint, is neutral: the cable hangs vertically from D wherever the pulley
  points), so P* there depends on the starting point and on round-off; |F(P*)| is still balanced.

References
----------
Paty et al. 2021, eq. (2)-(5), (10)-(14):
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263.

Pott, A., Cable-Driven Parallel Robots: Theory and Application, Springer 2018 (force equilibrium and
elastic cables of redundant CDPRs).
"""

from __future__ import annotations

import numpy as np

from cdpr.errors import CdprError
from cdpr.models.inverse import L_TS
from cdpr.models.pulleys import total_length_and_direction
from cdpr.models.results import STATUSES
from cdpr.models.statics import direction_gradient, length_gradient, solve3
from cdpr.robot import require_point_mass

#: Newton defaults: position tolerance [m], iteration cap, largest step [m].
PHYSICAL_DEFAULTS = {"tol": 1e-10, "maxiter": 60, "max_step": 0.5}
#: Armijo constant of the backtracking line search and its largest number of halvings.
ARMIJO_C = 1e-4
MAX_HALVINGS = 30
#: Steps shorter than this [m] are taken whole, without the line search.
LS_SKIP = 1e-4
#: A point is balanced when |F| <= FTOL_REL |w_ext|.
FTOL_REL = 1e-10
#: A cable counts as taut when its tension exceeds this [N]: below it, the tension is the round-off
#: of a cable resting at exactly its rest length (stretch ~1e-16 m).
TAUT_MIN = 1e-6
#: A start at or above the lowest joint point is moved to this distance [m] below it.
START_BELOW = 0.05
#: Distance [m] outside the anchors' horizontal convex hull tolerated as inside.
HULL_EPS = 1e-9
ST = {s: i for i, s in enumerate(STATUSES)}


def hull_halfplanes(robot):
    """Half-planes (n_x, n_y, c) of the anchors' horizontal convex hull, n . xy + c <= 0 inside
    (unit outward normals n), shape (n_edges, 3).

    A helper of the ``inaccessible`` status (no paper equation).

    Parameters
    ----------
    robot : Robot
        Supplies the joint points A (m, 3) [m].

    Returns
    -------
    halfplanes : ndarray (n_edges, 3)
        n_x, n_y [-] and c [m] per hull edge (``scipy.spatial.ConvexHull.equations``).
    """
    from scipy.spatial import ConvexHull  # lazy: scipy.spatial is 0.17 s of start-up

    return np.ascontiguousarray(ConvexHull(robot.A[:, :2]).equations)


def outside_frame(robot, P, halfplanes=None):
    """True where P (..., 3) [m] lies outside the anchors' horizontal convex hull (by more than
    ``HULL_EPS``) or at or above the lowest joint point; shape (...).

    Parameters
    ----------
    robot : Robot
        Supplies the joint points A (m, 3) [m].
    P : array_like (..., 3) [m]
        Positions.
    halfplanes : ndarray (n_edges, 3), optional
        ``hull_halfplanes(robot)``, computed when not given.

    Returns
    -------
    outside : ndarray (...) bool
        True where P is outside the frame (where gravity cannot be balanced by pulling cables, up
        to the pulley offsets, or above the pulleys).
    """
    hp = hull_halfplanes(robot) if halfplanes is None else halfplanes
    return _outside(np.asarray(P, dtype=float), hp, robot.A[:, 2].min())


def _outside(P, hp, z_top):
    """``outside_frame`` from the half-planes: P (..., 3) [m], hp (n_edges, 3) or, for a batch of
    robots, P (K, N, 3), hp (K, n_edges, 3) and z_top (K, 1) [m]. The signed distances are
    n_x x + n_y y + c, written out (the same operations for one robot and for a batch)."""
    hp = np.asarray(hp, dtype=float)
    if hp.ndim == 3:  # a batch: robot k's edges against robot k's points
        hp = hp[:, None]
    x, y = P[..., 0], P[..., 1]
    far = None  # the largest signed distance, edge by edge (no reduction over a short last axis)
    for e in range(hp.shape[-2]):
        d = x * hp[..., e, 0] + y * hp[..., e, 1] + hp[..., e, 2]
        far = d if far is None else np.maximum(far, d)
    return (far > HULL_EPS) | ~(P[..., 2] < z_top)


def _any_last(a):
    """a.any(axis=-1) for a short last axis (the cables), column by column: the same booleans,
    several times faster on (K, N, m) batches than numpy's reduction over an inner axis of 3-8."""
    out = a[..., 0].copy()
    for j in range(1, a.shape[-1]):
        out |= a[..., j]
    return out


class _Cables:
    """A robot's per-cable arrays and the pieces of the equilibrium: force, energy, Jacobian."""

    def __init__(self, robot):
        a = robot.arrays
        self.args = (a.A, a.kind, a.h, a.r_p, a.d, a.inward)
        self.ES = a.ES
        self.w_ext = robot.platform.w_ext
        self.ftol = FTOL_REL * float(np.linalg.norm(self.w_ext))
        self.z_top = float(a.A[:, 2].min())

    def evaluate(self, P, L0, p_ref, jacobian=True):
        """Cables at P (N, 3) with rest lengths L0 (N, m): dict of F (N, 3) [N], t (N, m) [N],
        taut (N, m), merit V (N,) [J] (infinite at or above the lowest joint point), the
        CableGeometry g and, with ``jacobian``: J = dF/dP (N, 3, 3) [N/m], grad = dV/dP (N, 3) [N]
        and kappa (N,) [N/m]."""
        g = total_length_and_direction(P, *self.args)
        e = g.L_TE - L0
        k = self.ES / L0
        taut = e > 0.0
        t = np.where(taut, k * e, 0.0)
        F = np.einsum("nj,nja->na", t, g.u) + self.w_ext
        merit = -(P - p_ref) @ self.w_ext + 0.5 * (k * np.where(taut, e, 0.0) ** 2).sum(axis=1)
        merit = np.where(P[:, 2] < self.z_top, merit, np.inf)
        out = {"F": F, "t": t, "taut": taut, "merit": merit, "g": g}
        if jacobian:
            act = e >= 0.0
            none = ~act.any(axis=1)
            act[none] = True  # no cable taut: Hooke extended to compression, in J and in Newton's F
            out["Fn"] = np.where(none[:, None], F + np.einsum("nj,nja->na", k * e, g.u), F)
            ka = k * act
            dL = length_gradient(g)
            out["J"] = np.einsum("nj,njab->nab", t, direction_gradient(g)) + np.einsum(
                "nj,nja,njb->nab", ka, g.u, dL
            )
            out["grad"] = np.einsum("nj,nja->na", t, dL) - self.w_ext
            out["kappa"] = ka.sum(axis=1) + (t / g.l_E).sum(axis=1)
        return out


def _take(state, idx, new, sel):
    """state[key][idx[sel]] = new[key][sel] for every array of a cables' evaluation."""
    for key in ("F", "Fn", "t", "taut", "merit", "J", "grad", "kappa"):
        state[key][idx[sel]] = new[key][sel]


def _newton(cab, P0, L0, p_ref, tol, maxiter, max_step):
    """Line-searched semismooth Newton over N points (see the module docstring).

    Returns P (N, 3), the evaluation at P (dict of arrays), iterations (N,), converged (N,)."""
    n = P0.shape[0]
    P = P0.copy()
    cur = cab.evaluate(P, L0, p_ref)
    cur.pop("g")
    iters = np.zeros(n, dtype=np.int32)
    conv = np.zeros(n, dtype=bool)
    prev = np.zeros(n)
    prev_full = np.zeros(n, dtype=bool)
    active = np.arange(n)
    for _ in range(maxiter):
        # balanced where it stands (this also stops the neutral swivel of a lone SR cable)
        here = np.einsum("na,na->n", cur["F"][active], cur["F"][active]) <= cab.ftol**2
        conv[active[here]] = True
        active = active[~here]
        if active.size == 0:
            break
        Fn, J, grad, merit, kappa = (cur[k][active] for k in ("Fn", "J", "grad", "merit", "kappa"))
        s, _ = solve3(J, -Fn)
        newton = np.isfinite(s).all(axis=1)
        s = np.where(newton[:, None], s, 0.0)
        slope = np.einsum("na,na->n", grad, s)
        newton &= (slope < 0.0) | (np.einsum("na,na->n", s, s) <= LS_SKIP**2)
        s = np.where(newton[:, None], s, -grad / np.where(kappa > 0, kappa, 1.0)[:, None])
        slope = np.einsum("na,na->n", grad, s)
        norm = np.linalg.norm(s, axis=1)
        done = newton & ((norm < tol) | (prev_full[active] & (norm * norm < tol * prev[active])))
        scale = np.where(done, 1.0, np.minimum(1.0, max_step / np.maximum(norm, 1e-300)))
        s *= scale[:, None]
        slope *= scale
        whole = done | (norm * scale <= LS_SKIP)

        def trial_at(pending, a):
            Pt = P[active[pending]] + a[:, None] * s[pending]
            return cab.evaluate(Pt, L0[active[pending]], p_ref[active[pending]]), Pt

        def accept(pending, trial, Pt, ok):
            P[active[pending[ok]]] = Pt[ok]
            _take(cur, active[pending], trial, ok)

        alpha = backtrack(trial_at, accept, merit, slope, whole)
        iters[active] += 1
        prev[active] = alpha * norm * scale
        prev_full[active] = newton & (alpha == 1.0) & (scale == 1.0)
        conv[active[done]] = True
        active = active[~done]
    return P, cur, iters, conv


def backtrack(trial_at, accept, merit, slope, whole):
    """Armijo backtracking line search over a batch of Newton steps (Nocedal & Wright 2006, alg. 3.1),
    the one both equilibria use (``_newton`` here, ``equilibrium6._newton6``): the step fraction
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


def per_point(a, n):
    """``a`` of shape (N,) or (N, k) as (N, k) rows per point; (0, 1) when there are no points (a
    reshape to (0, -1) is undefined).

    Parameters
    ----------
    a : array_like, shape (N,) or (N, k)
        A per-point quantity.
    n : int
        The number of points N.

    Returns
    -------
    ndarray (N, k)
    """
    a = np.asarray(a)
    return a.reshape(n, -1) if n else a.reshape(0, 1)


def statuses(robot, p, P, t, converged, inside, halfplanes=None):
    """Status codes (N,) int8 of ``STATUSES`` (module docstring, 'Edge cases'): inaccessible if p
    or P* is outside the frame (``outside_frame``) or P* inside a sheave or not finite, else
    not_converged (not converged, or no cable pulls), else over_tension if some t_i > T_a,i, else
    ok. For a desired point outside the frame, inaccessible wins over not_converged.

    Parameters
    ----------
    robot : Robot
        Supplies the joint points and the admissible tensions T_a (m,) [N].
    p : ndarray (N, 3) [m]
        Desired positions.
    P : ndarray (N, 3) [m]
        Equilibria P* (may hold NaN).
    t : ndarray (N, m) [N]
        Tensions, 0 on slack cables.
    converged : ndarray (N,) bool
        Newton converged.
    inside : ndarray (N, m) bool
        P* inside a sheave (``CableGeometry.inside``).
    halfplanes : ndarray (n_edges, 3), optional
        ``hull_halfplanes(robot)``, computed when not given.

    Returns
    -------
    code : ndarray (N,) int8
        Index into ``results.STATUSES``.
    """
    hp = [hull_halfplanes(robot) if halfplanes is None else halfplanes]
    inside = per_point(inside, len(p))  # (N,) or (N, m')
    P, t, converged, inside = (np.asarray(x)[None] for x in (P, t, converged, inside))
    return statuses_batch([robot], p, P, t, converged, inside, hp)[0]


def statuses_batch(robots, p, P, t, converged, inside, halfplanes=None):
    """``statuses`` of K robots solved at the same desired points, on the stacked arrays (one pass
    per number of hull edges instead of one per robot: the Monte Carlo and Sobol samples).

    Parameters
    ----------
    robots : sequence of Robot
        K robots with the same number of cables m.
    p : ndarray (N, 3) [m]
        Desired positions, shared.
    P : ndarray (K, N, 3) [m]
        Equilibria P* (may hold NaN).
    t : ndarray (K, N, m) [N]
    converged : ndarray (K, N) bool
    inside : ndarray (K, N, m') bool
        P* inside a sheave.
    halfplanes : list of ndarray (n_edges, 3), optional
        ``hull_halfplanes`` of each robot, computed (once per distinct set of anchors) when not given.

    Returns
    -------
    code : ndarray (K, N) int8
        Index into ``results.STATUSES``.
    """
    robots = list(robots)
    K = len(robots)
    if halfplanes is None:
        seen, halfplanes = {}, []
        for r in robots:
            key = r.A[:, :2].tobytes()
            if key not in seen:
                seen[key] = hull_halfplanes(r)
            halfplanes.append(seen[key])
    p = np.asarray(p, dtype=float)
    finite = ~_any_last(~np.isfinite(P))
    Pf = np.where(finite[..., None], P, 0.0)
    z_top = np.array([r.A[:, 2].min() for r in robots]).reshape(K, 1)
    bad_p = np.empty(finite.shape, dtype=bool)
    bad_P = np.empty(finite.shape, dtype=bool)
    by_edges = {}
    for k, hp in enumerate(halfplanes):
        by_edges.setdefault(len(hp), []).append(k)
    for ks in by_edges.values():
        H = np.stack([halfplanes[k] for k in ks])
        bad_p[ks] = _outside(np.broadcast_to(p, (len(ks), *p.shape)), H, z_top[ks])
        bad_P[ks] = _outside(Pf[ks], H, z_top[ks])
    bad_P |= ~finite | _any_last(inside)
    T_a = np.stack([r.T_a for r in robots])
    code = np.full(finite.shape, ST["ok"], dtype=np.int8)
    code[_any_last(t > T_a[:, None, :])] = ST["over_tension"]
    code[bad_P] = ST["inaccessible"]
    code[~converged | ~_any_last(t > TAUT_MIN)] = ST["not_converged"]  # no cable pulls: no equilibrium
    code[bad_p] = ST["inaccessible"]
    return code


def start_points(robot, P0):
    """Newton's starting points: P0 (N, 3) [m], moved down to ``START_BELOW`` under the lowest joint
    point where it lies higher than that (the model means nothing above the pulleys; this happens
    for a desired point above them, reported inaccessible).

    Parameters
    ----------
    robot : Robot
        Supplies the joint points A (m, 3) [m].
    P0 : array_like (N, 3) or (3,) [m]
        Starting points.

    Returns
    -------
    P0 : ndarray (N, 3) [m]
        A C-contiguous copy; z lowered to (lowest joint height - ``START_BELOW``) where it was
        above that level.
    """
    P0 = np.array(np.atleast_2d(np.asarray(P0, dtype=float)))
    top = robot.A[:, 2].min() - START_BELOW
    P0[:, 2] = np.where(P0[:, 2] < top, P0[:, 2], top)
    return np.ascontiguousarray(P0)


def solve_physical(robot, p, L0=None, P0=None, tol=None, maxiter=None, max_step=None):
    """Physical equilibrium P* of the platform on all m cables, with slack cables allowed.

    Solves sum_i t_i u_i(P*) + w_ext = 0 with t_i = E_i S_i max(0, L_TE,i(P*) - L0_i) / L0_i by a
    line-searched semismooth Newton (module docstring). Numpy reference; ``cdpr.compiled.equilibrium``
    is the compiled engine (same results, tested).

    Parameters
    ----------
    robot : Robot
    p : array_like, shape (N, 3) [m]
        Desired positions; the error is |dp| = |P* - p| (eq. 14).
    L0 : array_like, shape (N, m) [m], optional
        Commanded rest lengths; default L_TS(p) (eq. 2), as in the paper.
    P0 : array_like, shape (N, 3) [m], optional
        Newton's starting point, default p (``start_points``).
    tol, maxiter, max_step : float [m], int, float [m], optional
        Step tolerance, iteration cap, largest step; defaults ``PHYSICAL_DEFAULTS``.

    Returns
    -------
    dict
        p (N, 3) [m]; P_s (N, 3) [m] the equilibrium P*; dp (N,) [m]; t (N, m) [N], NaN on slack
        cables; taut (N, m) bool (t_i > ``TAUT_MIN``); n_taut (N,); residual (N,) [N] = |F(P*)|;
        iterations (N,); converged (N,) bool; status_code (N,) int8 and status (N,) str of
        ``results.STATUSES``.

    References
    ----------
    Paty et al. 2021, eq. (2)-(5), (10)-(14); physical mode of the project's model reading.
    """
    o = PHYSICAL_DEFAULTS
    tol = o["tol"] if tol is None else tol
    maxiter = o["maxiter"] if maxiter is None else maxiter
    max_step = o["max_step"] if max_step is None else max_step
    require_point_mass(
        robot, "solve_physical", 'cdpr.solve_points_any(robot, p, redundancy="physical")', True, p
    )
    p = np.atleast_2d(np.asarray(p, dtype=float))
    L0 = (
        L_TS(robot, p)
        if L0 is None
        else np.broadcast_to(np.asarray(L0, dtype=float), (len(p), robot.m)).copy()
    )
    P0 = start_points(robot, p if P0 is None else P0)
    cab = _Cables(robot)
    P, cur, iters, conv = _newton(cab, P0, L0, p, tol, maxiter, max_step)
    g = total_length_and_direction(P, *cab.args)
    return physical_result(robot, p, P, cur["t"], np.linalg.norm(cur["F"], axis=1), iters, conv, g.inside)


def solve_physical_batch(robots, p, L0=None, tol=None, maxiter=None, max_step=None, P0=None):
    """``solve_physical`` of several robots at the same points and rest lengths (Monte Carlo and
    Sobol samples of one design): the numpy reference of ``cdpr.compiled.equilibrium``'s batch
    kernel, which solves every (robot, point) pair in one parallel pass.

    Parameters
    ----------
    robots : sequence of Robot
        Robots with the same number of cables m.
    p : array_like, shape (N, 3) [m]
        Desired positions.
    L0 : array_like, shape (N, m) [m], optional
        Commanded rest lengths of every robot; default L_TS(p) (eq. 2) of each robot.
    tol, maxiter, max_step : float [m], int, float [m], optional
        As ``solve_physical``.
    P0 : array_like, shape (N, 3) or (K, N, 3) [m], optional
        Newton's starting points: the same for every robot, or robot k's in ``P0[k]`` (a warm start
        near each robot's equilibrium, ``uncertainty.PoseErrorModel``); default p.

    Returns
    -------
    list of dict
        ``solve_physical`` of each robot.
    """
    starts = batch_starts(robots, p, P0)
    return [solve_physical(r, p, L0, P, tol, maxiter, max_step) for r, P in zip(robots, starts)]


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


def physical_result(robot, p, P, t, residual, iters, conv, inside, halfplanes=None):
    """The result dict of ``solve_physical`` from the solved arrays (the compiled engines build
    theirs with it too): the taut cables (t > ``TAUT_MIN``), |dp| = |P* - p| (Paty 2021 eq. 14) and
    the statuses (``statuses``).

    Parameters
    ----------
    robot : Robot
    p : ndarray (N, 3) [m]
        Desired positions.
    P : ndarray (N, 3) [m]
        Solved positions P*.
    t : ndarray (N, m) [N]
        Hooke tensions at P* (0 for a slack cable).
    residual : ndarray (N,) [N]
        |F| of the force balance at P*.
    iters : ndarray (N,) int
    conv : ndarray (N,) bool
    inside : ndarray (N,) or (N, 1) bool
        p inside the anchors' horizontal convex hull.
    halfplanes : ndarray (n_edges, 3), optional
        ``hull_halfplanes(robot)``.

    Returns
    -------
    dict
        p, P_s, dp, t (NaN where slack), taut, n_taut, residual, iterations, converged,
        status_code (index into ``results.STATUSES``), status.
    """
    hp = None if halfplanes is None else [halfplanes]
    inside = per_point(inside, len(p))  # (N,) or (N, 1)
    arrays = (np.asarray(x)[None] for x in (P, t, residual, iters, conv, inside))
    return physical_results([robot], p, *arrays, halfplanes=hp)[0]


def physical_results(robots, p, P, t, residual, iters, conv, inside, halfplanes=None):
    """``physical_result`` of K robots solved at the same desired points, built on the stacked
    arrays (``statuses_batch``); each robot's dict holds views of its row.

    Parameters
    ----------
    robots : sequence of Robot
        K robots with the same number of cables m.
    p : ndarray (N, 3) [m]
    P : ndarray (K, N, 3) [m]
    t : ndarray (K, N, m) [N]
    residual : ndarray (K, N) [N]
    iters : ndarray (K, N) int
    conv : ndarray (K, N) bool
    inside : ndarray (K, N, m') bool
        P* inside a sheave (m' = 1: one flag per point, as the kernels give it).
    halfplanes : list of ndarray (n_edges, 3), optional

    Returns
    -------
    list of dict
        ``physical_result`` of each robot.
    """
    taut = t > TAUT_MIN
    code = statuses_batch(robots, p, P, t, conv, inside, halfplanes)
    d = P - p
    dp = np.sqrt(d[..., 0] * d[..., 0] + d[..., 1] * d[..., 1] + d[..., 2] * d[..., 2])  # |P* - p|
    tt = np.where(taut, t, np.nan)
    n_taut = taut[..., 0].astype(np.int8)
    for j in range(1, taut.shape[-1]):
        n_taut += taut[..., j]
    status = np.asarray(STATUSES)[code]
    return [
        {
            "p": p,
            "P_s": P[k],
            "dp": dp[k],
            "t": tt[k],
            "taut": taut[k],
            "n_taut": n_taut[k],
            "residual": residual[k],
            "iterations": iters[k],
            "converged": conv[k],
            "status_code": code[k],
            "status": status[k],
        }
        for k in range(len(code))
    ]
