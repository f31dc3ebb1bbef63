"""Exact first-order sensitivities of the solved pose, dP*/dθ, by the implicit-function theorem.

The solvers find P* with F(P*, θ) = 0 for the parameters θ of the robot. Where F is smooth and its
Jacobian J = dF/dP is regular, the solution moves with the parameters as

    dP*/dθ = -J^-1 dF/dθ

with the same J the Newton step already uses. Two sets of equations (``redundancy``):

* ``paper`` (DEGM_E on the chosen 3-cable subset, ``direct``): F_j = L_TE,j(P) - L_j (1 + t_j(P)/(E_j S_j)),
  t = M_u^-1 (-w_ext) the tensions of the three cables (eq. 11-13);
* ``physical`` (``equilibrium``): F = sum_i t_i u_i + w_ext, t_i = (E_i S_i / L0_i) max(0, L_TE,i - L0_i).

The commanded lengths (L, L0) are held fixed: they are what the winches were told, computed with the
nominal model, so dP*/dθ is how far the platform moves when the real robot's θ differs from the
model's. Parameters (``parameter_names``), cables numbered from 1: E_i [Pa], h_i, r_p_i, d_i [m],
A_i_x, A_i_y, A_i_z [m] and the payload mass M [kg].

Partial derivatives of one cable at fixed P (``cable_partials``), in the cable plane (``pulleys``):
moving the sheave centre H by dH changes the length by (u + u_C) . dH (u from P toward the exit point
D, u_C from the winch exit C toward the entry point K), and turns u by (I - u u^T) dH / |l_E|;
dH/dh is the arm direction (horizontal e_s for SR, the bisector for DR). A larger sheave radius
lengthens the cable by its wrap angle, dL_TE/dr_p = gamma, and turns u by n_D / |l_E|, n_D the
outward normal of the sheave at D. A longer dead length moves C down: dL_TE/dd = u_C . z. The
geometry of a cable depends on P - A_i only, so d/dA_i = -d/dP for both L_TE and u. The paper-mode
tensions are proportional to M and do not depend on E; Hooke's law gives the E and M terms.

Not differentiable (flagged ``smooth = False``, sensitivities still given): where the answer would
switch under a small change of θ. Paper mode: another admissible subset within ``GAP_TOL`` of the
chosen |dp| (e.g. on the diagonals of CDPR4, where two subsets tie), or a tension of the chosen subset
within ``T_TOL`` of 0 or T_a. Physical mode: a cable whose Hooke tension k_i (L_TE,i - L0_i) is within
``T_TOL`` of 0 (the taut set changes), or a taut cable within ``T_TOL`` of T_a. Either mode: a Jacobian
whose condition number exceeds ``COND_MAX`` (a platform on one SR or DR cable can swing round its
joint axis: a circle of equilibria, J singular). Points whose status is not ``ok`` get NaN.

The numpy functions here are the reference; ``cdpr.compiled.sensitivity`` computes the same in the
compiled engines' kernels, in the same pass as the solve (tested equal, and against central finite
differences of full solves).

At a pose
---------
Physical mode of any robot (a rigid platform, pulleys at any axis, a given orientation): at the
equilibrium x* = (p*, R*) under fixed commanded rest lengths L0 the force and moment balance F6(x*, θ) = 0 holds (``equilibrium``). Differentiating,

    dx*/dθ = -(dF6/dx)^-1 dF6/dθ,

with dF6/dx the solver's analytic 6 x 6 Jacobian (``cables._jacobian``; dφ a base-frame
rotation vector) and dF6/dθ the partial derivatives of the balance with respect to each parameter
at fixed pose, exact (``_wrench_partials``: ``cable_partials`` at each attachment point B_i =
p + R b_i, the formulas of the compiled twin ``compiled._pose_sensitivity.wrench_partials``, so the
two agree to round-off). θ is the spatial parameter vector of ``cdpr.parameters``
(``parameter_names(robot, rigid=True)``: E_i, h_i, r_p,i, d_i, A_i, the attachments b_i (platform frame), the centre
of mass c and the mass M).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (eq. 3-5, 10-14).
Implicit-function theorem, e.g. J. Nocedal and S. Wright, Numerical Optimization, 2nd ed.,
Springer 2006, A.2.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from cdpr.errors import CdprError
from cdpr.models.cables import Cables
from cdpr.models.direct import degm_e
from cdpr.models.equilibrium import solve as solve_equilibrium
from cdpr.models.inverse import L_TS
from cdpr.models.pulleys import pulley_state, total_length_and_direction
from cdpr.models.results import ok_point_sensitivities, point_keys
from cdpr.models.statics import direction_gradient, inverse3, length_gradient, tensions
from cdpr.models.subsets import solve_points
from cdpr.parameters import GROUPS, UNITS, parameter_names  # noqa: F401  (re-exported)

#: |dp| gap [m] to the runner-up admissible subset under which a paper-mode point is not smooth.
GAP_TOL = 1e-6
#: Tension margin [N] (to 0, to T_a, or of a slack cable's would-be tension) under which a point is
#: not smooth.
T_TOL = 1e-2
#: Condition number ||J||_F ||J^-1||_F above which a point is not smooth: the equilibrium is (close
#: to) not isolated, e.g. a platform hanging on one SR or DR cable, free to swing round its joint axis.
COND_MAX = 1e8


class CablePartials(NamedTuple):
    """Derivatives of every cable at fixed P (``cable_partials``); shapes (..., m) unless stated.

    u (..., m, 3): unit vector from P toward the exit point D; l_E [m]; dL_dP (..., m, 3) and
    du_dP (..., m, 3, 3) [1/m]: with respect to P; dL (..., m, 6) and du (..., m, 3, 6): with respect
    to the cable's own h, r_p, d, A_x, A_y, A_z (in that order; [m/m] and [1/m])."""

    u: np.ndarray
    l_E: np.ndarray
    L_TE: np.ndarray
    dL_dP: np.ndarray
    du_dP: np.ndarray
    dL: np.ndarray
    du: np.ndarray


def cable_partials(P, A, kind, h, r_p, d, inward, frame=None, per_cable=False):
    """Partial derivatives of every cable's total length L_TE and direction u at P with respect to
    its own pulley parameters and joint point (module docstring)::

        dL_TE/dh = (u + u_C) . b,      du/dh = (I - u u^T) b / |l_E|
        dL_TE/dr_p = gamma,            du/dr_p = n_D / |l_E|
        dL_TE/dd = u_C . k,            du/dd = 0
        dL_TE/dA = -dL_TE/dP,          du/dA = -du/dP

    with k the pulley's swivel axis (+z in the paper), b the arm direction (SR and fixed: e_s, the
    cable plane's direction perpendicular to k; DR: the bisector), u_C the unit vector from the
    winch exit C = A - d k toward the entry point K, gamma the wrap angle, n_D = (u . k) e_s -
    (u . e_s) k the sheave's outward normal at D (in the cable plane, perpendicular to u).

    Parameters
    ----------
    P : array_like, shape (..., 3) [m]
        Platform positions.
    A : ndarray, shape (m, 3) [m]
        Joint points.
    kind : ndarray, shape (m,)
        Pulley kind codes 0 fixed / 1 SR / 2 DR.
    h, r_p, d : ndarray, shape (m,) [m]
        Lever arms, sheave radii, dead lengths.
    inward : ndarray, shape (m, 2)
        Fallback pulley-plane directions (``robot.CableArrays``).
    frame : ndarray, shape (m, 3, 3), optional
        Pulley frames, rows i_i, j_i, k_i (``Robot.arrays.frame``); None: k = +z with today's
        arithmetic (the suspended robots of the paper).
    per_cable : bool
        P is (..., m, 3), one attachment point B_i per cable (a rigid platform); the derivatives
        by P are then by B_i.

    Returns
    -------
    CablePartials
        u (..., m, 3); l_E, L_TE (..., m) [m]; dL_dP (..., m, 3); du_dP (..., m, 3, 3) [1/m];
        dL (..., m, 6) and du (..., m, 3, 6) with respect to h, r_p, d, A_x, A_y, A_z.

    References
    ----------
    Paty et al. 2021, eq. (3)-(5).
    """
    P = np.asarray(P, dtype=float)
    st = pulley_state(P, A, kind, h, r_p, d, inward, frame, per_cable)
    g = total_length_and_direction(P, A, kind, h, r_p, d, inward, frame, per_cable)
    u = g.u
    l_d = np.where(st.l_d > 0, st.l_d, 1.0)
    if frame is None:  # k = +z: the components directly (today's arithmetic, bit for bit)
        zero = np.zeros_like(st.rho)
        e3 = np.stack([st.e_s[..., 0], st.e_s[..., 1], zero], axis=-1)
        z = np.array([0.0, 0.0, 1.0])
        u_C = (st.K - A + d[:, None] * z) / l_d[..., None]  # C = A - d z
        beta_k, u_k, uC_k = g.beta[..., 2:3], u[..., 2:3], u_C[..., 2]
    else:
        e3 = st.e_s3
        z = frame[:, 2]  # the swivel axes k_i (m, 3)
        u_C = (st.K - A + d[:, None] * z) / l_d[..., None]  # C = A - d k
        beta_k = np.einsum("...ma,ma->...m", g.beta, z)[..., None]
        u_k = np.einsum("...ma,ma->...m", u, z)[..., None]
        uC_k = np.einsum("...ma,ma->...m", u_C, z)
    # arm direction: DR the bisector (beta rotated back by 90 degrees in the plane), else e_s
    bis = beta_k * e3 - np.einsum("...i,...i->...", g.beta, e3)[..., None] * z
    b = np.where((np.asarray(kind) == 2)[:, None], bis, e3)
    u_e = np.einsum("...i,...i->...", u, e3)
    n_D = u_k * e3 - u_e[..., None] * z
    lE = g.l_E[..., None]
    ub = np.einsum("...i,...i->...", u, b)
    dL = np.stack(
        [
            np.einsum("...i,...i->...", u + u_C, b),
            st.gamma,
            uC_k,
        ],
        axis=-1,
    )
    du = np.stack([(b - ub[..., None] * u) / lE, n_D / lE, np.zeros_like(u)], axis=-1)
    dL_dP = length_gradient(g)
    du_dP = direction_gradient(g)
    return CablePartials(
        u=u,
        l_E=g.l_E,
        L_TE=g.L_TE,
        dL_dP=dL_dP,
        du_dP=du_dP,
        dL=np.concatenate([dL, -dL_dP], axis=-1),
        du=np.concatenate([du, -du_dP], axis=-1),
    )


def _column_index(m):
    """Columns of (E, h, r_p, d) of cable c: c, m + c, 2 m + c, 3 m + c; A_c: 4 m + 3 c + (0, 1, 2); M: 7 m."""
    return {"E": 0, "h": m, "r_p": 2 * m, "d": 3 * m, "A": 4 * m, "M": 7 * m}


def _geo_columns(m, c):
    """The 6 columns of cable c's h, r_p, d, A_x, A_y, A_z (order of ``CablePartials.dL``)."""
    return [m + c, 2 * m + c, 3 * m + c, 4 * m + 3 * c, 4 * m + 3 * c + 1, 4 * m + 3 * c + 2]


def paper_jacobian_terms(robot, P, subset, L):
    """Jacobian and parameter derivatives of paper mode's equations for one 3-cable subset.

    F_j = L_TE,j(P) - L_j (1 + t_j(P) / (E_j S_j)), t = M_u^-1 (-w_ext) (eq. 11-13).

    Parameters
    ----------
    robot : Robot
    P : ndarray, shape (n, 3) [m]
        Solutions P* of the subset.
    subset : array_like of 3 int
        0-based cable indices.
    L : ndarray, shape (n, 3) [m]
        Commanded lengths of the subset's cables.

    Returns
    -------
    J : ndarray, shape (n, 3, 3)
        dF/dP [m/m].
    dF : ndarray, shape (n, 3, 7 m + 1)
        dF/dθ at fixed P [m per unit of θ].
    t : ndarray, shape (n, 3) [N]
        Tensions of the subset.
    dt_dP : ndarray, shape (n, 3, 3) [N/m]
    dt_part : ndarray, shape (n, 3, 7 m + 1)
        dt/dθ at fixed P; the total dt/dθ = dt_dP dP*/dθ + dt_part.

    References
    ----------
    Paty et al. 2021, eq. (3)-(5), (10)-(13).
    """
    a = robot.arrays
    s = np.asarray(subset, dtype=np.intp)
    m = robot.m
    K = 7 * m + 1
    frame = None if robot.suspended_point_mass else a.frame[s]  # as ``direct.degm_e``
    cp = cable_partials(P, a.A[s], a.kind[s], a.h[s], a.r_p[s], a.d[s], a.inward[s], frame)
    t, Minv = tensions(cp.u, robot.platform.w_ext)
    ES = a.ES[s]
    kL = L / ES  # (n, 3)
    G = np.einsum("nj,njab->nab", t, cp.du_dP)
    dt_dP = -Minv @ G
    J = cp.dL_dP - kL[..., None] * dt_dP
    n = len(P)
    dF = np.zeros((n, 3, K))
    dt_part = np.zeros((n, 3, K))
    for j, c in enumerate(s):
        dF[:, j, c] = kL[:, j] * t[:, j] / a.E[c]
        # geometric parameters of cable c: its length and, through its direction, every tension
        dt = -np.einsum("nab,nbk->nak", Minv, t[:, j, None, None] * cp.du[:, j])  # (n, 3, 6)
        block = -kL[..., None] * dt
        block[:, j, :] += cp.dL[:, j]
        dF[:, :, _geo_columns(m, c)] = block
        dt_part[:, :, _geo_columns(m, c)] = dt
    # the mass moves the weight only, not an external force (``Platform.wrench``): dt/dM = M_u^-1 (-M g) / M
    t_g = tensions(cp.u, robot.platform.gravity_force)[0] if robot.platform.has_wrench else t
    dF[:, :, 7 * m] = -kL * t_g / robot.platform.mass
    dt_part[:, :, 7 * m] = t_g / robot.platform.mass
    return J, dF, t, dt_dP, dt_part


def physical_jacobian_terms(robot, P, L0):
    """Jacobian and parameter derivatives of the physical force balance.

    F = sum_i t_i u_i + w_ext, t_i = (E_i S_i / L0_i) max(0, L_TE,i - L0_i).

    Parameters
    ----------
    robot : Robot
    P : ndarray, shape (n, 3) [m]
        Equilibria P*.
    L0 : ndarray, shape (n, m) [m]
        Rest lengths.

    Returns
    -------
    J : ndarray, shape (n, 3, 3) [N/m]
    dF : ndarray, shape (n, 3, 7 m + 1)
        dF/dθ at fixed P [N per unit of θ].
    hooke : ndarray, shape (n, m) [N]
        k_i (L_TE,i - L0_i), negative where the cable is slack (its tension is 0 then).

    References
    ----------
    Paty et al. 2021, eq. (10)-(13); the physical mode of ``equilibrium``.
    """
    a = robot.arrays
    m = robot.m
    K = 7 * m + 1
    cp = cable_partials(P, a.A, a.kind, a.h, a.r_p, a.d, a.inward)
    k = a.ES / L0
    hooke = k * (cp.L_TE - L0)
    taut = hooke >= 0.0
    t = np.where(taut, hooke, 0.0)
    ka = k * taut
    J = np.einsum("nj,njab->nab", t, cp.du_dP) + np.einsum("nj,nja,njb->nab", ka, cp.u, cp.dL_dP)
    n = len(P)
    dF = np.zeros((n, 3, K))
    for c in range(m):
        dF[:, :, c] = (t[:, c] / a.E[c])[:, None] * cp.u[:, c]
        dF[:, :, _geo_columns(m, c)] = (
            ka[:, c, None, None] * cp.u[:, c, :, None] * cp.dL[:, c, None, :]
            + t[:, c, None, None] * cp.du[:, c]
        )
    dF[:, :, 7 * m] = robot.platform.gravity_force / robot.platform.mass  # the weight, not the wrench
    return J, dF, hooke


def implicit_solve(J, dF):
    """dP*/dθ = -J^-1 dF/dθ for batches (the implicit-function theorem).

    Parameters
    ----------
    J : ndarray, shape (..., 3, 3)
        Jacobian dF/dP at the solutions.
    dF : ndarray, shape (..., 3, K)
        dF/dθ at fixed P.

    Returns
    -------
    S : ndarray, shape (..., 3, K)
        dP*/dθ [m per unit of θ], NaN where J is singular.
    cond : ndarray, shape (...)
        ||J||_F ||J^-1||_F, inf where J is singular.
    """
    Jinv, _ = inverse3(J)
    cond = np.linalg.norm(J, axis=(-2, -1)) * np.linalg.norm(Jinv, axis=(-2, -1))
    return -Jinv @ dF, np.where(np.isfinite(cond), cond, np.inf)


def _paper_flags(robot, res, L_sub_t):
    """dp gap to the runner-up admissible subset [m] and the tension margin [N] of paper mode."""
    subs = robot.subsets
    chosen = res["subset"]
    key = chosen @ np.array([robot.m * robot.m, robot.m, 1])
    skey = subs @ np.array([robot.m * robot.m, robot.m, 1])
    k = np.searchsorted(skey, key)
    has = chosen[:, 0] >= 0
    k = np.where(has, np.minimum(k, len(subs) - 1), 0)
    dp = np.where(res["admissible_subsets"], res["dp_subsets"], np.inf)
    dp[np.arange(len(k)), k] = np.inf
    gap = dp.min(axis=1) - res["dp"]
    t = L_sub_t
    T_a = robot.T_a[np.where(has[:, None], chosen, 0)]
    margin = np.minimum(t, T_a - t).min(axis=1)
    return np.where(has, gap, np.nan), np.where(has, margin, np.nan)


def sensitivities(
    robot,
    p,
    redundancy="paper",
    L=None,
    gap_tol=GAP_TOL,
    t_tol=T_TOL,
    **solver,
):
    """Solve the points and return dP*/dθ for every parameter, with a smoothness flag per point
    (the numpy reference; ``cdpr.solve.sensitivities`` chooses between it and the compiled twin
    ``cdpr.compiled.sensitivity.sensitivities_fast``).

    .. math:: \\frac{dP^*}{d\\theta} = -J^{-1} \\frac{\\partial F}{\\partial \\theta}

    Parameters
    ----------
    robot : Robot
        The model at its nominal parameters.
    p : array_like, shape (N, 3) [m]
        Desired positions.
    redundancy : {"paper", "physical"}
        Paper mode's best 3-cable subset (DEGM_E) or the physical equilibrium on all cables.
    L : array_like, shape (N, m) [m], optional
        Commanded lengths (paper: total lengths L; physical: rest lengths L0), held fixed; default
        L_TS(p) (eq. 2).
    gap_tol : float [m]
        |dp| gap to the runner-up admissible subset under which a paper-mode point is not smooth.
    t_tol : float [N]
        Tension margin under which a point is not smooth.
    solver : tol, maxiter (and max_step, physical mode) of the solve.

    Returns
    -------
    dict
        The solve's result (``subsets.solve_points`` / ``results.POINT_KEYS`` of ``equilibrium.solve``)
        plus: S (N, 3, 7 m + 1) [m per unit of θ], NaN where the status is not ok; names (list of
        7 m + 1 str, ``parameter_names``); smooth (N,) bool; margin_t (N,) [N] the tension margin;
        cond (N,) the condition number of J (inf where singular or not ok); paper mode also
        dp_gap (N,) [m], the |dp| gap to the runner-up admissible subset (inf if none).

    References
    ----------
    Paty et al. 2021, eq. (3)-(5), (10)-(14).
    """
    p = np.atleast_2d(np.asarray(p, dtype=float))
    if redundancy not in ("paper", "physical"):
        raise CdprError(f"unknown redundancy {redundancy!r}; allowed: paper, physical")
    n, m = len(p), robot.m
    L = L_TS(robot, p) if L is None else np.broadcast_to(np.asarray(L, dtype=float), (n, m))
    S = np.full((n, 3, 7 * m + 1), np.nan)
    if redundancy == "paper":
        res = solve_points(robot, p, L=L, **solver)
        ok = res["status"] == "ok"
        t_sub = np.full((n, 3), np.nan)
        cond = np.full(n, np.inf)
        for s in robot.subsets:
            idx = np.flatnonzero(ok & (res["subset"] == s).all(axis=1))
            if idx.size == 0:
                continue
            J, dF, t, _, _ = paper_jacobian_terms(robot, res["P_s"][idx], s, L[idx][:, s])
            S[idx], cond[idx] = implicit_solve(J, dF)
            t_sub[idx] = t
        gap, margin = _paper_flags(robot, res, t_sub)
        res["dp_gap"] = gap
        smooth = ok & (gap > gap_tol) & (margin > t_tol) & (cond < COND_MAX)
    else:
        res = point_keys(solve_equilibrium(robot, p, L0=L, **solver))
        ok = res["status"] == "ok"
        idx = np.flatnonzero(ok)
        margin = np.full(n, np.nan)
        cond = np.full(n, np.inf)
        if idx.size:
            J, dF, hooke = physical_jacobian_terms(robot, res["P_s"][idx], L[idx])
            S[idx], cond[idx] = implicit_solve(J, dF)
            over = np.where(hooke > 0, robot.T_a - hooke, np.inf)
            margin[idx] = np.minimum(np.abs(hooke).min(axis=1), over.min(axis=1))
        smooth = ok & (margin > t_tol) & (cond < COND_MAX)
    S[~ok] = np.nan
    res.update(S=S, names=parameter_names(robot, rigid=False), smooth=smooth, margin_t=margin, cond=cond)
    return res


def sensitivity_columns(names):
    """Table column names of the sensitivities: dx_d<name>, dy_d<name>, dz_d<name> per parameter.

    Parameters
    ----------
    names : list of str
        ``parameter_names``.

    Returns
    -------
    columns : list of str, length 3 len(names)
    """
    return [f"d{ax}_d{nm}" for nm in names for ax in "xyz"]


def subset_sensitivities(robot, p, L=None, columns=None, **solver):
    """Every 3-cable subset of paper mode at every point: P* (DEGM_E), its tensions, dP*/dθ and
    dt/dθ; for the first-order propagation when the best subset may switch
    (``uncertainty.Linearisation``). The numpy reference (``direct.degm_e`` and
    ``paper_jacobian_terms`` per subset); ``cdpr.solve.subset_sensitivities`` chooses between it and
    the compiled twin ``cdpr.compiled.sensitivity.subset_sensitivities``.

    Parameters
    ----------
    robot : Robot
    p : array_like, shape (N, 3) [m]
    L : array_like, shape (N, m) [m], optional
        Commanded lengths, default L_TS(p).
    columns : sequence of int, optional
        Parameter columns to keep, default all 7 m + 1.
    solver : tol, maxiter of the solves.

    Returns
    -------
    dict
        P (N, n_subsets, 3) [m]; t (N, n_subsets, 3) [N] the subset's tensions at P*; converged
        (N, n_subsets) (a regular solution: S is finite there); admissible (N, n_subsets);
        S (N, n_subsets, 3, len(columns)) dP*/dθ and St (same shape) dt/dθ [N per unit], NaN where
        not converged; T_a (n_subsets, 3) [N]; columns.

    References
    ----------
    Paty et al. 2021, eq. (8)-(13), section 3.2.
    """
    p = np.atleast_2d(np.asarray(p, dtype=float))
    n, m = len(p), robot.m
    cols = np.arange(7 * m + 1) if columns is None else np.asarray(columns, dtype=np.intp)
    L = L_TS(robot, p) if L is None else np.broadcast_to(np.asarray(L, dtype=float), (n, m))
    ns = len(robot.subsets)
    P = np.empty((n, ns, 3))
    t = np.full((n, ns, 3), np.nan)
    conv = np.zeros((n, ns), dtype=bool)
    S = np.full((n, ns, 3, len(cols)), np.nan)
    St = np.full((n, ns, 3, len(cols)), np.nan)
    for k, s in enumerate(robot.subsets):
        r = degm_e(robot, p, subset=s, L=L[:, s], **solver)
        P[:, k] = r.P
        idx = np.flatnonzero(r.converged)
        if idx.size:
            J, dF, tk, dt_dP, dt_part = paper_jacobian_terms(robot, r.P[idx], s, L[idx][:, s])
            Sk, cond = implicit_solve(J, dF)
            good = np.isfinite(cond)
            g = idx[good]
            S[g, k] = Sk[good][:, :, cols]
            St[g, k] = (dt_dP[good] @ Sk[good] + dt_part[good])[:, :, cols]
            t[g, k] = tk[good]
            conv[g, k] = True
    T_a = robot.T_a[robot.subsets]  # (ns, 3)
    adm = conv & (t >= 0).all(axis=2) & (t <= T_a).all(axis=2)
    return {
        "P": P,
        "t": t,
        "converged": conv,
        "admissible": adm,
        "S": S,
        "St": St,
        "T_a": T_a,
        "columns": cols,
    }


#: Parameter samples per batch of ``linear_dp`` (bounds the (batch, N, slots, 3) arrays).
BATCH = 16


def linear_dp(dp0, S, valid, delta, t0=None, St=None, T_a=None):
    """First-order propagation: the smallest ‖dp‖ over the admissible linearised slots of every
    point, for every parameter change (the numpy reference of ``uncertainty.Linearisation.dp``;
    ``cdpr.compiled.sensitivity.linear_dp`` is its compiled twin).

    .. math:: dp(\\theta) = \\min_{c\\ \\mathrm{admissible}} \\lVert dp_{0,c} + S_c \\delta \\rVert,
              \\quad t_c(\\theta) = t_{0,c} + S_{t,c} \\delta

    with δ = τ(θ) - τ(θ_0); a slot is admissible where it is valid and (paper mode) its linearised
    tensions stay within 0 <= t <= T_a.

    Parameters
    ----------
    dp0 : ndarray, shape (N, C, 3) [m]
        Nominal error of every slot (C subsets in paper mode, 1 in physical mode).
    S : ndarray, shape (N, C, 3, k) [m per unit of τ]
        Sensitivities of the slots (in τ, see ``uncertainty.Linearisation``).
    valid : ndarray, shape (N, C) bool
    delta : ndarray, shape (n, k) [unit of τ]
        τ(θ) - τ(θ_0) per sample.
    t0 : ndarray, shape (N, C, 3) [N], optional
    St : ndarray, shape (N, C, 3, k) [N per unit of τ], optional
    T_a : ndarray, shape (C, 3) [N], optional
        Tensions, their sensitivities and the admissible tensions (paper mode).

    Returns
    -------
    dp : ndarray, shape (n, N) [m]
        NaN where no slot is admissible.

    References
    ----------
    Paty et al. 2021, eq. (8)-(13), section 3.2 (the subset rule applied to the linearised slots).
    """
    has_t = t0 is not None
    N, C, _, k = S.shape
    Sflat = S.reshape(N * C * 3, k)
    Stflat = St.reshape(N * C * 3, k) if has_t else None
    out = np.empty((len(delta), N))
    for i in range(0, len(delta), BATCH):
        d = delta[i : i + BATCH]
        v = (Sflat @ d.T).T.reshape(len(d), N, C, 3) + dp0
        adm = valid
        if has_t:
            t = (Stflat @ d.T).T.reshape(len(d), N, C, 3) + t0
            adm = adm & (t >= 0).all(axis=3) & (t <= T_a).all(axis=3)
        norm = np.where(adm, np.linalg.norm(v, axis=3), np.inf)
        out[i : i + BATCH] = norm.min(axis=2)
    return np.where(np.isfinite(out), out, np.nan)


def linear_positions(dp0, S, delta):
    """First-order positions of one slot for every parameter change: the linearised P*(θ) - p
    (the numpy reference of ``uncertainty.Linearisation.shift``; ``cdpr.compiled.sensitivity.
    linear_positions`` is its compiled twin). Full solves start from p + this (a warm start).

    .. math:: P^*(\\theta) - p \\approx dp_0 + S \\delta, \\quad \\delta = \\tau(\\theta) - \\tau(\\theta_0)

    Parameters
    ----------
    dp0 : ndarray, shape (N, 3) [m]
        Nominal error P*(θ_0) - p of the slot.
    S : ndarray, shape (N, 3, k) [m per unit of τ]
        Its sensitivities (in τ, see ``uncertainty.Linearisation``).
    delta : ndarray, shape (n, k) [unit of τ]
        τ(θ) - τ(θ_0) per sample.

    Returns
    -------
    ndarray, shape (n, N, 3) [m]

    References
    ----------
    Paty et al. 2021, eq. (8)-(13) (the sensitivities), section 3.2.
    """
    N, _, k = S.shape
    return (S.reshape(N * 3, k) @ np.asarray(delta, dtype=float).T).T.reshape(len(delta), N, 3) + dp0


def pose_columns(robot, names=None):
    """The columns of ``names`` in ``parameter_names(robot, rigid=True)`` (the pose kernels' dF6/dθ).

    Parameters
    ----------
    robot : Robot
    names : list of str, optional
        Parameters (default all of ``parameter_names(robot, rigid=True)``).

    Returns
    -------
    names : list of str
    cols : ndarray of int, shape (len(names),)

    Raises
    ------
    CdprError
        A name that is not a 6-DoF parameter of the robot.
    """
    every = parameter_names(robot, rigid=True)
    names = every if names is None else list(names)
    index = {nm: k for k, nm in enumerate(every)}
    bad = [nm for nm in names if nm not in index]
    if bad:
        raise CdprError(
            f"unknown 6-DoF parameter(s) {', '.join(map(repr, bad))}; allowed: parameter_names(robot, rigid=True) "
            f"({every[0]} ... {every[-1]})"
        )
    return names, np.array([index[nm] for nm in names], dtype=np.intp)


#: Per-cable partials (``_cable_terms``): E, h, r_p, d, A_x, A_y, A_z, b_x, b_y, b_z.
PER_CABLE = 10


def _cable_terms(cab, P, R, L0):
    """Every cable's tension and its partials at fixed poses (P (n, 3), R (n, 3, 3)) and rest
    lengths L0 (n, m), exact (``cable_partials`` at B_i = p + R b_i): t (n, m) [N] (0 on a slack
    cable), u (n, m, 3), r = R b (n, m, 3) [m] and, for cable i's own E_i, h_i, r_p_i, d_i, A_i_xyz,
    b_i_xyz (``PER_CABLE`` columns, in that order), dt (n, m, 10) [N per unit], du (n, m, 3, 10)
    [1 per unit] and dr (n, m, 3, 10) [m per unit]::

        dt_i = a_i k_i dL_TE,i (t_i / E_i for E_i),  dL_TE/dA = -dL_TE/dB,  du/dA = -du/dB,
        dr/db_a = dB/db_a = R e_a,  dL_TE/db_a = dL_TE/dB . R e_a,  du/db_a = du/dB R e_a.
    """
    A, kind, h, r_p, d, inward, frame = cab.args
    r = np.einsum("nab,mb->nma", R, cab.b)
    cp = cable_partials(P[:, None, :] + r, A, kind, h, r_p, d, inward, frame, per_cable=True)
    k = cab.ES / L0
    e = cp.L_TE - L0
    ka = np.where(e > 0.0, k, 0.0)
    t = ka * e
    n, m = t.shape
    dL = np.zeros((n, m, PER_CABLE))
    du = np.zeros((n, m, 3, PER_CABLE))
    dr = np.zeros((n, m, 3, PER_CABLE))
    dL[..., 1:7] = cp.dL
    du[..., 1:7] = cp.du
    dL[..., 7:] = np.einsum("nmb,nba->nma", cp.dL_dP, R)
    du[..., 7:] = np.einsum("nmcb,nba->nmca", cp.du_dP, R)
    dr[..., 7:] = R[:, None]
    dt = ka[..., None] * dL
    dt[..., 0] = t / cab.E
    return t, cp.u, r, dt, du, dr


def _cable_column_index(m):
    """Column (in ``parameter_names(robot, rigid=True)``) of cable c's j-th ``_cable_terms``
    partial: an (m, PER_CABLE) int array."""
    c = np.arange(m)[:, None]
    a = np.arange(3)[None, :]
    return np.concatenate([c, m + c, 2 * m + c, 3 * m + c, 4 * m + 3 * c + a, 7 * m + 3 * c + a], axis=1)


def _wrench_partials(cab, P, R, L0):
    r"""dF6/dθ, the partial derivatives of the force and moment balance with respect to every
    parameter at fixed poses and rest lengths, exact (the numpy twin of the compiled
    ``_pose_sensitivity.wrench_partials``, same formulas).

    With w_i = t_i (u_i, r_i × u_i), t_i = a_i k_i (L_TE,i - L0_i), k_i = E_i S_i / L0_i, r_i = R b_i:

    .. math:: \frac{\partial w_i}{\partial q} = dt_i \begin{bmatrix} u_i \\ r_i \times u_i
              \end{bmatrix} + t_i \begin{bmatrix} du_i \\ dr_i \times u_i + r_i \times du_i
              \end{bmatrix}

    for q = E_i, h_i, r_p,i, d_i, A_i, b_i (``_cable_terms``), and dF6/dc_a = (0, R e_a × f),
    dF6/dM = (f, R c × f) / M (f = M g the weight: an external wrench, ``Platform.wrench``, is constant
    in the world frame and depends on no parameter); the moment rows are 0 on a point mass.

    Parameters
    ----------
    cab : Cables
        The robot's cables (``_cables``: with E and M).
    P : ndarray, shape (n, 3) [m]
        Platform positions.
    R : ndarray, shape (n, 3, 3) [-]
        Orientations.
    L0 : ndarray, shape (n, m) [m]
        Rest lengths.

    Returns
    -------
    dF : ndarray, shape (n, 6, 10 m + 4)
        d(F, M)/dθ [N, N m per unit of θ], columns of ``parameter_names(robot, rigid=True)``.
    t : ndarray, shape (n, m) [N]
        The tensions (0 on a slack cable).

    References
    ----------
    Paty et al. 2021, eq. (3)-(5), (10)-(13).
    """
    t, u, r, dt, du, dr = _cable_terms(cab, P, R, L0)
    n, m = t.shape
    ue, re = u[..., None], r[..., None]
    force = dt[:, :, None, :] * ue + t[:, :, None, None] * du
    moment = dt[:, :, None, :] * np.cross(r, u)[..., None] + t[:, :, None, None] * (
        np.cross(dr, ue, axis=2) + np.cross(re, du, axis=2)
    )
    dF = np.zeros((n, 6, 10 * m + 4))
    cols = _cable_column_index(m).ravel()
    dF[:, :3, cols] = np.moveaxis(force, 2, 1).reshape(n, 3, m * PER_CABLE)
    dF[:, 3:, cols] = np.moveaxis(moment, 2, 1).reshape(n, 3, m * PER_CABLE)
    f = cab.robot.platform.gravity_force  # the weight (a point mass's cab.f adds the wrench's force)
    dF[:, 3:, 10 * m : 10 * m + 3] = np.swapaxes(np.cross(np.swapaxes(R, 1, 2), f), 1, 2)  # R e_a x f
    dF[:, :3, 10 * m + 3] = f / cab.mass
    dF[:, 3:, 10 * m + 3] = np.cross(R @ cab.com, f) / cab.mass
    if not cab.rigid:
        dF[:, 3:] = 0.0
    return dF, t


def _cables(robot):
    """The robot's ``Cables`` with the moduli E and the mass M the partials need."""
    cab = Cables(robot)
    cab.mass = robot.platform.mass
    cab.E = robot.arrays.E
    return cab


def tension_partials(robot, P, R, L0, names=None):
    r"""The cable tensions at fixed poses of a rigid platform and their partial derivatives by the
    pose, the rest lengths and the parameters.

    .. math:: t_i = a_i k_i (L_{TE,i}(B_i) - L0_i),\quad k_i = \frac{E_i S_i}{L0_i},\quad
              B_i = p + R b_i,

    .. math:: \frac{\partial t_i}{\partial (p, \varphi)} = a_i k_i
              \left[\frac{\partial L_{TE,i}}{\partial B},\;
              r_i \times \frac{\partial L_{TE,i}}{\partial B}\right],\quad
              \frac{\partial t_i}{\partial L0_i} = -a_i k_i \frac{L_{TE,i}}{L0_i}

    (dB_i = dp + dφ × r_i, r_i = R b_i, φ a base-frame rotation vector; a_i = 1 on a taut cable,
    L_TE,i ≥ L0_i); ∂t_i/∂θ at fixed pose and rest lengths exact (the ``_wrench_partials`` terms:
    a_i k_i ∂L_TE,i/∂θ, t_i/E_i for E_i) for E_i, h_i, r_p_i, d_i, A_i, b_i, and 0 for the centre
    of mass and the mass (they move the tensions only through the pose).

    Parameters
    ----------
    robot : Robot
    P : ndarray, shape (n, 3) [m]
        Platform positions.
    R : ndarray, shape (n, 3, 3) [-]
        Orientations.
    L0 : ndarray, shape (n, m) [m]
        Rest lengths.
    names : list of str, optional
        Parameters (``parameter_names(robot, rigid=True)``; default all).

    Returns
    -------
    dict
        t (n, m) [N] (0 on a slack cable); dt_dx (n, m, 6) [N/m, N/rad]; dt_dL0 (n, m) [N/m]
        (cable i's own rest length); dt_dtheta (n, m, len(names)) [N per unit of θ].

    References
    ----------
    Paty et al. 2021, eq. (5), (10), (13) (the total length and Hooke's law at B_i).
    """
    names, cols = pose_columns(robot, names)
    cab = _cables(robot)
    r = np.einsum("nab,mb->nma", R, cab.b)
    g = total_length_and_direction(P[:, None, :] + r, *cab.args, per_cable=True)
    k = cab.ES / L0
    e = g.L_TE - L0
    ka = k * (e >= 0.0)
    dL = length_gradient(g)
    n, m = len(P), robot.m
    out = {
        "t": ka * e,
        "dt_dx": ka[..., None] * np.concatenate([dL, np.cross(r, dL)], axis=-1),
        "dt_dL0": -ka * g.L_TE / L0,
        "dt_dtheta": np.zeros((n, m, len(names))),
    }
    if n:
        dt = _cable_terms(cab, P, R, L0)[3]
        full = np.zeros((n, m, 10 * m + 4))
        full[:, np.arange(m)[:, None], _cable_column_index(m)] = dt
        out["dt_dtheta"] = full[:, :, cols]
    return out


def pose_sensitivity_columns(names):
    """Table column names of the 6-DoF sensitivities: dx_d<name>, dy_d<name>, dz_d<name> [m per
    unit] then dphix_d<name>, dphiy_d<name>, dphiz_d<name> [rad per unit] per parameter.

    Parameters
    ----------
    names : list of str
        ``parameter_names(robot, rigid=True)``.

    Returns
    -------
    columns : list of str, length 6 len(names)
    """
    return [f"d{ax}_d{nm}" for nm in names for ax in ("x", "y", "z", "phix", "phiy", "phiz")]


def scaled_condition(J, ell, rigid=True):
    """Condition number ||J_s||_F ||J_s^-1||_F of the balance's Jacobian in consistent units,
    J_s = D^-1 J D^-1 with D = diag(1, 1, 1, ell, ell, ell) (moments per ell, rotations times ell:
    every entry in N/m); the 3 x 3 translation block for a platform without moments (``rigid``
    False). inf where J is singular or not finite.

    Parameters
    ----------
    J : ndarray (N, 6, 6) [N/m, N/rad, N m/m, N m/rad]
        d(F, M)/d(dp, dphi) (``cables._jacobian``).
    ell : float [m]
        The platform's size (``Cables.size``).
    rigid : bool
        Whether the moment rows count.

    Returns
    -------
    cond : ndarray (N,) [-]
    """
    D = np.array([1.0, 1.0, 1.0, ell, ell, ell])
    Js = J / D[:, None] / D[None, :]
    if not rigid:
        Js = Js[:, :3, :3]
    cond = np.full(len(J), np.inf)
    ok = np.isfinite(Js).all(axis=(1, 2))
    if ok.any():
        s = np.linalg.svd(Js[ok], compute_uv=False)
        with np.errstate(divide="ignore"):
            c = np.sqrt((s**2).sum(axis=1)) * np.sqrt((1.0 / s**2).sum(axis=1))
        cond[ok] = np.where(s[:, -1] > 0, c, np.inf)
    return cond


def sensitivities_at(robot, res, names=None, t_tol=T_TOL):
    """dp*/dθ and dφ*/dθ at the equilibria of a ``solve_spatial`` result (implicit-function theorem),
    with the smoothness flag of the point-mass physical mode.

    .. math:: \\frac{dx^*}{d\\theta} = -\\left(\\frac{\\partial F_6}{\\partial x}\\right)^{+}
        \\frac{\\partial F_6}{\\partial \\theta}, \\qquad x = (\\mathbf p, \\boldsymbol\\varphi)

    Parameters
    ----------
    robot : Robot
        The model at its nominal parameters.
    res : dict
        A ``solve_spatial`` result (P_s (N, 3) [m], R_s (N, 3, 3), L0 (N, m) [m], status (N,)), from
        either engine.
    names : list of str, optional
        Parameters (default ``parameter_names(robot, rigid=True)``); another name raises CdprError
        (``pose_columns``).
    t_tol : float [N]
        Tension margin under which a point is not smooth (``sensitivity.T_TOL``).

    Returns
    -------
    dict
        names (n,); S (N, 6, n): rows dp_x, dp_y, dp_z [m per unit of θ] and dφ_x, dφ_y, dφ_z [rad
        per unit of θ] (base-frame rotation vector), NaN where the status is not ok; smooth (N,)
        bool: ok, every cable's Hooke tension (E_i S_i/L0_i)(L_TE,i - L0_i) (the would-be one of a
        slack cable) more than ``t_tol`` from 0 and from T_a (the taut set is not about to change)
        and ``scaled_condition`` below ``sensitivity.COND_MAX`` (the Jacobian is not singular), as
        ``sensitivity.sensitivities`` decides it for a point mass; margin_t (N,) [N]; cond (N,).

    References
    ----------
    Paty et al. 2021 (parameters); implicit-function theorem on Pott 2018's elastic equilibrium.
    """
    names, cols = pose_columns(robot, names)

    def at(idx):
        cab = _cables(robot)
        P, R, L0 = res["P_s"][idx], res["R_s"][idx], np.asarray(res["L0"])[idx]
        ev = cab.evaluate(P, R, L0, P)
        J = ev["J"]
        dF = _wrench_partials(cab, P, R, L0)[0][:, :, cols]
        S = -np.einsum("nab,nbk->nak", np.linalg.pinv(J, rcond=1e-12), dF)
        hooke = cab.ES / L0 * (ev["g"].L_TE - L0)
        over = np.where(hooke > 0, robot.T_a - hooke, np.inf)
        margin = np.minimum(np.abs(hooke).min(axis=1), over.min(axis=1))
        return S, margin, scaled_condition(J, cab.size, cab.rigid)

    return ok_point_sensitivities(res, names, at, t_tol, COND_MAX)


def pose_sensitivities(robot, p, rotvec=None, L0=None, names=None, t_tol=T_TOL, **solver):
    """dp*/dθ and dφ*/dθ at the equilibria under fixed commanded rest lengths (the numpy reference:
    ``solve_spatial`` then ``sensitivities_at``).

    Parameters
    ----------
    robot : Robot
    p : array_like (N, 3) or (N, 6) [m, rad]
        Desired positions or poses.
    rotvec : array_like (N, 3) or (3,) [rad], optional
        Desired orientations.
    L0 : array_like (N, m) [m], optional
        Commanded rest lengths (default L_TS at the desired pose), held fixed.
    names : list of str, optional
        Parameters (default ``parameter_names(robot, rigid=True)``).
    t_tol : float [N]
        Tension margin of the smoothness flag (``sensitivities_at``).
    solver : options of ``solve_spatial`` (tol, maxiter, max_step, restarts, P0).

    Returns
    -------
    dict
        The ``solve_spatial`` result and names (n,), S (N, 6, n): rows dp_x, dp_y, dp_z [m per
        unit of θ] and dφ_x, dφ_y, dφ_z [rad per unit of θ] (base-frame rotation vector), NaN where
        the status is not ok; smooth (N,), margin_t (N,) [N], cond (N,) (``sensitivities_at``).

    References
    ----------
    Paty et al. 2021 (parameters); implicit-function theorem on Pott 2018's elastic equilibrium.
    """
    res = solve_equilibrium(robot, p, rotvec, L0=L0, **solver)
    res.update(sensitivities_at(robot, res, names, t_tol))
    return res


def rest_length_sensitivities(robot, P, R, L0):
    r"""dx*/dL0 of the equilibrium pose by the commanded rest lengths, and the Hooke tensions.

    .. math:: \frac{dx^*}{dL0_i} = -\left(\frac{dF_6}{dx}\right)^{-1}
              \frac{\partial F_6}{\partial L0_i},\quad
              \frac{\partial F_6}{\partial L0_i} = -a_i \frac{E_i S_i}{L0_i}
              \frac{L_{TE,i}}{L0_i} \begin{bmatrix} u_i \\ r_i \times u_i \end{bmatrix}

    (t_i = E_i S_i (L_TE,i - L0_i) / L0_i, a_i = 1 on a taut cable, r_i = R b_i); x = (p, φ), φ a
    base-frame rotation vector.

    Parameters
    ----------
    robot : Robot
    P : ndarray, shape (n, 3) [m]
        Equilibrium positions.
    R : ndarray, shape (n, 3, 3) [-]
        Equilibrium orientations.
    L0 : ndarray, shape (n, m) [m]
        Rest lengths.

    Returns
    -------
    S : ndarray, shape (n, 6, m) [m/m, rad/m]
        Rows dp_x, dp_y, dp_z, dφ_x, dφ_y, dφ_z.
    hooke : ndarray, shape (n, m) [N]
        k_i (L_TE,i - L0_i), negative on a slack cable (its distance to becoming taut).
    cond : ndarray, shape (n,)
        Condition number of dF6/dx (inf where singular).

    References
    ----------
    Paty et al. 2021, eq. (10)-(13); implicit-function theorem.
    """
    cab = Cables(robot)
    ev = cab.evaluate(P, R, L0, P)
    g = ev["g"]
    k = cab.ES / L0
    e = g.L_TE - L0
    r = np.einsum("nab,mb->nma", R, cab.b)
    w = -((e >= 0) * k * g.L_TE / L0)  # (n, m)
    dF = np.concatenate(
        [w[:, None, :] * np.swapaxes(g.u, 1, 2), w[:, None, :] * np.swapaxes(np.cross(r, g.u), 1, 2)], axis=1
    )
    J = ev["J"]
    S = -np.einsum("nab,nbk->nak", np.linalg.pinv(J, rcond=1e-12), dF)
    with np.errstate(all="ignore"):
        cond = np.linalg.cond(J)
    return S, k * e, np.where(np.isfinite(cond), cond, np.inf)
