"""Choice of the cables that hold the platform and the per-point status (paper mode, section 3.2).

Every 3-cable subset is solved with DEGM_E. A subset is admissible at a point when its solution
exists, converged, and 0 <= t_j <= T_a at P*. The point's answer is the admissible subset with the
lowest |dp| (Fig. 8-9). Ties (e.g. on the diagonals of CDPR4, where two subsets give the same
|dp| mathematically) are broken deterministically: among subsets within ``TIE_TOL`` of the
minimum, the first in lexicographic order of cable numbers wins.

Status of a point (``results.STATUSES``):
  ok             an admissible subset exists;
  over_tension   some subset converged with all tensions >= 0 but one above T_a, none admissible;
  slack          subsets converged but each needs a negative (pushing) tension;
  not_converged  a subset's solver hit its iteration cap and no subset converged;
  inaccessible   no subset has a geometric solution (spheres do not meet, point above the
                 pulleys, point inside a sheave, coplanar cables).
For a point that is not ``ok``, the solved position and tensions of the converged subset with the
lowest |dp| are still reported, so that the reason can be inspected; aggregations keep ``ok`` rows.

The pose error is Paty 2021 eq. (14), |dp| = |P* - p|, with P* the DEGM_E solution for the commanded
lengths L_TS(p) of eq. (2).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263.
"""

from __future__ import annotations

import numpy as np

from cdpr.errors import CdprError
from cdpr.models.direct import degm_e
from cdpr.models.inverse import L_TS
from cdpr.robot import require_point_mass

#: |dp| difference [m] under which two admissible subsets count as tied.
TIE_TOL = 1e-9


def solve_points(robot, p, method="newton", L=None, P0=None, **options):
    """Solve DEGM_E at desired points p (N, 3) over all 3-cable subsets; choose per point.

    Every subset is commanded the lengths ``L`` (default the standard lengths L_TS(p), Paty 2021
    eq. 2) and solved with
    ``direct.degm_e``; the pose error is |dp| = |P* - p| (eq. 14); the choice and the statuses are
    those of the module docstring (section 3.2, Fig. 8-9).

    Parameters
    ----------
    robot : Robot
        Supplies the cables, ``subsets`` and the admissible tensions T_a (m,) [N].
    p : array_like (N, 3) [m]
        Desired positions.
    method : {"newton", "fixed_point"}
        DEGM_E solver (``direct.degm_e``).
    L : array_like (N, m) [m], optional
        Commanded total lengths of every cable; default L_TS(p) of ``robot`` (eq. 2).
    P0 : array_like (N, n_subsets, 3) [m], optional
        The solver's start of every subset at every point (``direct.degm_e``); default p.
    options : tolerances passed to ``direct.degm_e``.

    Returns
    -------
    dict
        Arrays: p (N, 3) [m]; P_s (N, 3) [m] the chosen solution P* (NaN when no subset
        converged); dp (N,) [m]; t (N, m) [N] with NaN for slack cables; subset (N, 3) 0-based
        (-1 when none); iterations (N,); status (N,) strings of ``results.STATUSES``; and the per-subset
        dp_subsets (N, n_subsets) [m] and admissible_subsets (N, n_subsets) bool for maps such as
        Fig. 9.
    """
    require_point_mass(
        robot, "paper mode (solve_points)", 'cdpr.solve.solve(robot, p, redundancy="physical")', P=p
    )
    p = np.atleast_2d(np.asarray(p, dtype=float))
    n = p.shape[0]
    subsets = robot.subsets
    ns = len(subsets)
    L_all = L_TS(robot, p) if L is None else np.broadcast_to(np.asarray(L, dtype=float), (n, robot.m))
    T_a = robot.T_a[subsets][:, None, :]  # (n_subsets, 1, 3) per-cable admissible tension
    Ps = np.full((ns, n, 3), np.nan)
    ts = np.full((ns, n, 3), np.nan)
    its = np.zeros((ns, n), dtype=np.int32)
    conv = np.zeros((ns, n), dtype=bool)
    exists = np.zeros((ns, n), dtype=bool)
    if P0 is not None:
        P0 = np.asarray(P0, dtype=float)
        if P0.shape != (n, ns, 3):
            raise CdprError(f"P0 has shape {P0.shape}; allowed: (N, subsets, 3) = ({n}, {ns}, 3)")
    for k, s in enumerate(subsets):
        start = None if P0 is None else P0[:, k]
        r = degm_e(robot, p, subset=s, L=L_all[:, s], method=method, P0=start, **options)
        Ps[k], ts[k], its[k], conv[k], exists[k] = r.P, r.t, r.iterations, r.converged, r.exists
    dp = np.linalg.norm(Ps - p, axis=2)
    t_ok_low = (ts >= 0).all(axis=2)
    t_ok_high = (ts <= T_a).all(axis=2)
    admissible = conv & t_ok_low & t_ok_high
    # choose: admissible with min dp, else converged with min dp (for reporting only)
    dp_adm = np.where(admissible, dp, np.inf)
    dp_conv = np.where(conv, dp, np.inf)
    any_adm = admissible.any(axis=0)
    key = np.where(any_adm, dp_adm, dp_conv)
    best = key.min(axis=0)
    tied = key <= best + TIE_TOL
    choice = np.argmax(tied, axis=0)  # first (lexicographic) subset among the tied ones
    has = np.isfinite(best)
    cols = np.arange(n)
    status = np.full(n, "inaccessible", dtype=object)
    status[(~conv & exists).any(axis=0)] = "not_converged"
    status[conv.any(axis=0)] = "slack"
    status[(conv & t_ok_low).any(axis=0)] = "over_tension"
    status[any_adm] = "ok"
    t_full = np.full((n, robot.m), np.nan)
    chosen = np.where(has[:, None], subsets[choice], -1)
    for j in range(3):
        t_full[cols[has], chosen[has, j]] = ts[choice[has], cols[has], j]
    P_s = np.where(has[:, None], Ps[choice, cols], np.nan)
    return {
        "p": p,
        "P_s": P_s,
        "dp": np.where(has, dp[choice, cols], np.nan),
        "t": t_full,
        "subset": chosen,
        "iterations": its[choice, cols],
        "status": status.astype(str),
        "dp_subsets": dp.T,
        "admissible_subsets": admissible.T,
    }
