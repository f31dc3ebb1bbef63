"""Direct elasto-geometric model DEGM_E (Paty et al. 2021, section 2.2.3).

Given commanded total lengths L (by default L_TS from the standard inverse model at the desired
point), find the actual platform position P* such that, for each of the three taut cables j,

    L_TE,j(P*) = L_j (1 + t_j(P*) / (E S))

with t(P*) the tensions that hold the platform at P* (eq. 11-13). Two solvers behind one interface
(``method``): ``"newton"`` (batched Newton, default) and ``"fixed_point"`` (the paper's nested
scheme: sphere intersections, eq. 8-9, inside updates of the tensions). Both are vectorised over
points and report iterations and convergence per point.

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cdpr.models.inverse import L_TS
from cdpr.models.pulleys import pulley_state, total_length_and_direction
from cdpr.models.statics import length_gradient, solve3, stretched_length, tension_gradient, tensions
from cdpr.robot import require_point_mass

#: Newton defaults: position tolerance [m] (see _newton), iteration cap, largest step [m].
NEWTON_DEFAULTS = {"tol": 1e-10, "maxiter": 40, "max_step": 0.5}
#: Fixed-point defaults: stop criterion eps_P [m] (paper: 1e-5 m), caps of inner and outer loops.
FIXED_POINT_DEFAULTS = {"tol": 1e-5, "max_inner": 200, "max_outer": 100}


@dataclass
class DirectResult:
    """Solution of DEGM_E for one 3-cable subset over N points.

    P: (N, 3) solved position [m]; t: (N, 3) tensions [N] of the subset's cables; iterations (N,);
    converged (N,) bool; exists (N,) bool (False where no geometric solution: spheres that do not
    meet, coplanar cables, P* inside a sheave).
    """

    P: np.ndarray
    t: np.ndarray
    iterations: np.ndarray
    converged: np.ndarray
    exists: np.ndarray


class _Subset:
    """Per-cable parameters of a fixed 3-cable subset, ready for the kernels."""

    def __init__(self, robot, subset):
        s = np.asarray(subset, dtype=np.intp)
        self.args = (robot.A[s], robot.kind[s], robot.h[s], robot.r_p[s], robot.d[s], robot.inward[s])
        self.A = self.args[0]
        self.ES = robot.ES[s]
        self.w_ext = robot.platform.w_ext
        # a suspended robot (axes +z) keeps today's arithmetic (frame None) and its accessibility
        # rule (P below every pulley); pulleys at other axes are evaluated in their frames
        self.suspended = robot.suspended_point_mass
        self.frame = None if self.suspended else robot.arrays.frame[s]
        down = np.asarray(robot.platform.down, dtype=float)
        self.down = None if self.suspended else down / np.linalg.norm(down)  # gravity's direction

    def geometry(self, P):
        return total_length_and_direction(P, *self.args, frame=self.frame)

    def residual(self, P, L, jacobian=False):
        """F = L_TE(P) - L (1 + t(P)/(E S)), its tensions, a validity flag and, if asked
        (``jacobian``), the Jacobian dF/dP = dL_TE/dP - diag(L / E S) dt/dP and dt/dP."""
        g = self.geometry(P)
        t, M_inv = tensions(g.u, self.w_ext)
        F = g.L_TE - stretched_length(L, t, self.ES)
        valid = ~g.inside.any(axis=-1) & np.isfinite(F).all(axis=-1)
        if self.suspended:
            valid &= (P[:, None, 2] < self.A[:, 2]).all(axis=-1)
        if not jacobian:
            return F, t, valid
        dt = tension_gradient(t, M_inv, g)
        return F, t, valid, length_gradient(g) - (L / self.ES)[..., None] * dt, dt


def _newton(sub, P0, L, tol, maxiter, max_step):
    """Batched Newton on F(P) = 0 with the analytic Jacobian; steps capped at ``max_step``.

    A point converges when the step s_k just computed is shorter than ``tol``, or when the error
    left after taking it, estimated from the observed contraction as |s_k|^2 / |s_(k-1)| (s_(k-1)
    the step taken, after the ``max_step`` cap), is below ``tol``: this bounds the error for linear
    convergence and over-estimates it for quadratic convergence. That last step is taken and the
    tensions are carried to the new P to first order (t + dt/dP s_k); this saves the evaluation
    that would only confirm convergence. A point also stops when no step exists. Returns P, iterations, converged, exists, the tensions and validity
    at the returned P, and ``fresh`` (False where the iteration cap left P moved after its last
    evaluation)."""
    n = P0.shape[0]
    P = P0.copy()
    iters = np.zeros(n, dtype=np.int32)
    conv = np.zeros(n, dtype=bool)
    exists = np.ones(n, dtype=bool)
    t_at = np.full((n, 3), np.nan)
    valid_at = np.zeros(n, dtype=bool)
    fresh = np.zeros(n, dtype=bool)
    prev = np.zeros(n)  # length of each point's previous step taken (0: none yet)
    active = np.arange(n)
    for _ in range(maxiter):
        if active.size == 0:
            break
        Pa, La = P[active], L[active]
        F, t, valid, J, dt = sub.residual(Pa, La, jacobian=True)
        step, _ = solve3(J, -F)
        bad = ~valid | ~np.isfinite(step).all(axis=1)
        step = np.where(bad[:, None], 0.0, step)
        norm = np.linalg.norm(step, axis=1)
        done = ((norm < tol) | (norm * norm < tol * prev[active])) & ~bad
        scale = np.where(done, 1.0, np.minimum(1.0, max_step / np.maximum(norm, 1e-300)))
        P[active] = Pa + step * scale[:, None]
        t_at[active] = np.where(done[:, None], t + np.einsum("...ij,...j->...i", dt, step), t)
        valid_at[active] = valid
        fresh[active] = bad | done
        iters[active] += 1
        exists[active[bad]] = False
        conv[active[done]] = True
        prev[active] = norm * scale  # length of the step taken
        active = active[~(bad | done)]
    return P, iters, conv, exists, t_at, valid_at, fresh


def trilaterate_low(c, R, down=None):
    """Lower intersection of three spheres with centres c (N, 3, 3) and radii R (N, 3), eq. (9).

    Paty 2021 eq. (9): |P - H_j|^2 = R_j^2, j = 1, 2, 3, with the sheave centres H_j and the radii
    R_j = sqrt((L_j - |l_d,j| - gamma_j r_p,j)^2 + r_p,j^2) of eq. (8); of the two solutions the
    "low" one (smaller z) is kept, the only one a hanging platform reaches.

    With ``down`` (gravity's direction, for pulleys at any axis) the kept solution is the one on
    gravity's side of the plane of the centres, base + z e_z with e_z . down > 0 (the paper's rule
    for down = -z): three cables pulling the platform toward that plane can hold it against gravity
    with positive tensions only from that side (n . u_j > 0 for the normal n toward the plane, and
    sum t_j u_j = -M g down needs n . down < 0), and the rule turns with the robot.

    Parameters
    ----------
    c : ndarray (N, 3, 3) [m]
        Sphere centres, one per row (``c[:, j]`` is H_j).
    R : ndarray (N, 3) [m]
        Sphere radii.
    down : ndarray (3,) [-], optional
        Unit gravity direction; None: -z with the paper's arithmetic (smaller z).

    Returns
    -------
    P : ndarray (N, 3) [m]
        The lower intersection point; where the spheres do not meet, the point where their radical
        line crosses the plane of the three centres (meaningless, flagged by ``exists``).
    exists : ndarray (N,) bool
        False where the spheres do not meet.
    """
    c1, c2, c3 = c[:, 0], c[:, 1], c[:, 2]
    v12 = c2 - c1
    dd = np.linalg.norm(v12, axis=1)
    ex = v12 / dd[:, None]
    v13 = c3 - c1
    i = np.einsum("ij,ij->i", ex, v13)
    ey = v13 - i[:, None] * ex
    ey_n = np.linalg.norm(ey, axis=1)
    ey = ey / ey_n[:, None]
    ez = np.cross(ex, ey)
    j = np.einsum("ij,ij->i", ey, v13)
    r1, r2, r3 = R[:, 0], R[:, 1], R[:, 2]
    x = (r1**2 - r2**2 + dd**2) / (2 * dd)
    y = (r1**2 - r3**2 + i**2 + j**2) / (2 * j) - i * x / j
    z2 = r1**2 - x**2 - y**2
    exists = z2 >= 0
    z = np.sqrt(np.maximum(z2, 0.0))
    base = c1 + x[:, None] * ex + y[:, None] * ey
    # the lower of base +/- z ez (along gravity: the side ez . down > 0)
    if down is None:
        sign = np.where(ez[:, 2] > 0, -1.0, 1.0)
    else:
        sign = np.where(ez @ down > 0, 1.0, -1.0)
    return base + (sign * z)[:, None] * ez, exists


def _fixed_point(sub, P0, L0, tol, max_inner, max_outer):
    """The paper's nested scheme (Fig. 6): an inner DGM_E loop of sphere intersections (eq. 8-9)
    updating the pulleys at fixed lengths, and an outer loop updating tensions and stretched
    lengths (eq. 11-13). Both stop when the position moves less than ``tol``. ``iterations`` counts
    sphere intersections. Pulleys at any axis: each in its frame, the intersection kept on
    gravity's side (``trilaterate_low`` with ``down``)."""
    A, kind, h, r_p, d, inward = sub.args
    n = P0.shape[0]
    P = P0.copy()
    L = L0.copy()
    iters = np.zeros(n, dtype=np.int32)
    conv = np.zeros(n, dtype=bool)
    exists = np.ones(n, dtype=bool)
    active = np.arange(n)
    for _outer in range(max_outer):
        if active.size == 0:
            break
        P_prev = P[active].copy()
        inner = active
        for _inner in range(max_inner):
            if inner.size == 0:
                break
            st = pulley_state(P[inner], A, kind, h, r_p, d, inward, sub.frame)
            arm = L[inner] - st.l_d - st.gamma * r_p
            R = np.sqrt(arm**2 + r_p**2)
            Pn, ok = trilaterate_low(st.H, R, sub.down)
            ok &= ~st.inside.any(axis=1) & (arm > 0).all(axis=1)
            iters[inner] += 1
            exists[inner[~ok]] = False
            step = np.linalg.norm(Pn - P[inner], axis=1)
            P[inner[ok]] = Pn[ok]
            inner = inner[ok & (step >= tol)]
        keep = exists[active]
        active, P_prev = active[keep], P_prev[keep]
        u = sub.geometry(P[active]).u
        t, _ = tensions(u, sub.w_ext)
        L[active] = stretched_length(L0[active], t, sub.ES)
        done = np.linalg.norm(P[active] - P_prev, axis=1) < tol
        conv[active[done]] = True
        active = active[~done]
    return P, iters, conv, exists


def degm_e(robot, p, subset=(0, 1, 2), L=None, method="newton", P0=None, **options):
    """Solve DEGM_E for one 3-cable subset at N points.

    Finds P* with L_TE,j(P*) = L_j (1 + t_j(P*) / (E_j S_j)) for the three cables j of the subset
    (Paty 2021 eq. 5, 10-13; the tensions t(P*) from eq. 11-12).

    Parameters
    ----------
    robot : Robot
    p : array_like (N, 3) [m]
        Desired positions; the commanded lengths default to L_TS(p) (eq. 2).
    subset : sequence of 3 int
        Three 0-based cable indices that hold the platform; the others are slack.
    L : array_like (N, 3) [m], optional
        Commanded rest lengths of the subset's cables, default L_TS(p)[:, subset].
    method : {"newton", "fixed_point"}
        Batched Newton (default) or the paper's nested fixed point (Fig. 6).
    P0 : array_like (N, 3) [m], optional
        Starting point, default p.
    options : tolerances, see NEWTON_DEFAULTS and FIXED_POINT_DEFAULTS.

    Returns
    -------
    DirectResult
        P (N, 3) [m], t (N, 3) [N], iterations (N,), converged (N,) bool, exists (N,) bool;
        tensions are evaluated at the returned P.
    """
    require_point_mass(robot, "paper mode (degm_e)", 'cdpr.solve.solve(robot, p, redundancy="physical")', P=p)
    p = np.atleast_2d(np.asarray(p, dtype=float))
    s = np.asarray(subset, dtype=np.intp)
    sub = _Subset(robot, s)
    if L is None:
        L = L_TS(robot, p)[:, s]
    P0 = p if P0 is None else np.atleast_2d(np.asarray(P0, dtype=float))
    if method == "newton":
        opts = {**NEWTON_DEFAULTS, **options}
        P, iters, conv, exists, t, valid, fresh = _newton(sub, P0, L, **opts)
        if not fresh.all():  # iteration cap reached: evaluate where P moved last
            stale = ~fresh
            _, t[stale], valid[stale] = sub.residual(P[stale], L[stale])
    elif method == "fixed_point":
        opts = {**FIXED_POINT_DEFAULTS, **options}
        P, iters, conv, exists = _fixed_point(sub, P0, L, **opts)
        _, t, valid = sub.residual(P, L)
    else:
        raise ValueError(f"unknown DEGM_E method {method!r}; allowed: 'newton', 'fixed_point'")
    exists &= valid
    conv &= exists
    return DirectResult(P=P, t=t, iterations=iters, converged=conv, exists=exists)
