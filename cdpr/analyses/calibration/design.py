"""The measurement plan: where to measure (``plan``).

Candidate poses of a box (``candidates``: admissible, smooth nominal equilibria), their scaled
measurement rows (``info_rows``), a greedy D-optimal choice with one exchange pass
(``d_optimal``), compared with random plans of the same size (``plan_sd``).

References
----------
Atkinson, A. C., Donev, A. N. (1992). Optimum Experimental Designs, Oxford, ch. 11 (D-optimality)
and 15 (exchange algorithms).
"""

from __future__ import annotations

import numpy as np

from cdpr.analyses.calibration.data import (
    SIGMA_DEFAULT,
    Data,
)
from cdpr.analyses.calibration.estimator import (
    parse_priors,
    prior_sd,
)
from cdpr.analyses.calibration.model import (
    check_command,
    commanded_lengths,
    equilibria,
    model_robot,
    realised_lengths,
)
from cdpr.analyses.calibration.problem import (
    Problem,
)
from cdpr.analyses.workspace import check_box, grid_points
from cdpr.errors import CdprError
from cdpr.models.inverse import L_TS
from cdpr.models.platform import rotation_matrix
from cdpr.parameters import (
    calibration_groups,
    calibration_names,
    is_spatial,
    select_groups,
)

#: The tilt [rad] of a rigid platform's candidate orientations beside the identity (10°): candidates
#: at one orientation cannot separate an anchor A_i from an attachment b_i (both move the cable the
#: same way), tilted ones can.
TILT_RAD = float(np.deg2rad(10.0))
#: A group whose every parameter keeps at least this share of its prior sd after the plan is one the
#: plan cannot see (``plan``'s warnings).
BLIND_RATIO = 0.8


def candidate_orientations(robot, tilt=TILT_RAD):
    """The orientations a robot's candidates are commanded at: the identity only for a point mass;
    for a rigid platform (``is_spatial``) also ±``tilt`` about x, y and z.

    Parameters
    ----------
    robot : Robot
    tilt : float [rad]

    Returns
    -------
    rotvec : ndarray (o, 3) [rad]
        Rotation vectors, the identity first.
    """
    if not is_spatial(robot) or robot.point_mass:
        return np.zeros((1, 3))
    return np.vstack([np.zeros(3), *(s * tilt * np.eye(3)[k] for k in range(3) for s in (1.0, -1.0))])


def default_box(robot):
    """Candidate box: the middle 80 % of the anchors' horizontal extent, z from 10 % to 70 % of
    the lowest anchor height [m]; for a 6-DoF robot whose anchors spread in height (some low, some
    high), z from 20 % to 80 % of the anchors' vertical span."""
    A = robot.A
    lo, hi = A[:, :2].min(axis=0), A[:, :2].max(axis=0)
    c, w = (lo + hi) / 2, (hi - lo) / 2 * 0.8
    top = A[:, 2].min()
    zlo, zhi = 0.1 * top, 0.7 * top
    span = A[:, 2].max() - top
    if is_spatial(robot) and (top <= 0 or span > 0.1 * abs(top)):  # anchors low and high (IPAnema-like)
        zlo, zhi = top + 0.2 * span, top + 0.8 * span
    return [c[0] - w[0], c[0] + w[0], c[1] - w[1], c[1] + w[1], zlo, zhi]


def candidates(robot, box, n_axis=7, model="exact", engine=None, targets=False, command="standard"):
    """Admissible candidate poses of a box and their scaled measurement rows.

    A candidate is the grid point p commanded with L_TS(p); admissible when the nominal equilibrium
    is ``ok`` and smooth there. A 6-DoF platform's candidates are at the identity orientation and
    tilted by ±``TILT_RAD`` about x, y and z (``candidate_orientations``; L_TS,i = |p + R b_i - A_i|
    + d_i, or with ``command="compensated"`` the compensated rest lengths, ``commanded_lengths``),
    admissible with at least min(6, m) taut cables; a point mass's with at least 3 (``equilibria``:
    the pose model when a pulley axis is not +z).

    Returns
    -------
    P : ndarray (c, 3) [m], or (c, 6) [m, rad] for a 6-DoF platform
        The equilibria (where the tracker would measure).
    L0 : ndarray (c, m) [m]
        Commanded lengths.
    p : ndarray (c, 3) [m]
        The grid points commanded (only with ``targets=True``).
    """

    base = model_robot(robot, model)
    p = grid_points(box, n_axis)
    spatial = is_spatial(robot)
    rv = None
    if spatial:
        rv = candidate_orientations(robot)  # every grid point at every orientation, identity first
        rv = np.repeat(rv, len(p), axis=0)
        p = np.tile(p, (len(rv) // len(p), 1))
        L0 = commanded_lengths(robot, p, rotation_matrix(rv), command)
        fin = np.isfinite(L0).all(axis=1)
        p, L0, rv = p[fin], L0[fin], rv[fin]
    else:
        L0 = L_TS(robot, p)
    L_real = realised_lengths(base, L0)  # through the drums of a robot with winches
    drum = np.isfinite(L_real).all(axis=1)
    res = equilibria(base, p, np.where(drum[:, None], L_real, L0), rotvec=rv, engine=engine)
    ok = (
        (res["status"] == "ok")
        & res["smooth"]
        & (res["n_taut"] >= (min(6, robot.m) if spatial else 3))
        & drum
    )
    P = np.concatenate([res["P_s"], res["rotvec_s"]], axis=1) if spatial else res["P_s"]
    return (P[ok], L0[ok], p[ok]) if targets else (P[ok], L0[ok])


def info_rows(robot, P, L0, index, sd, sigma=SIGMA_DEFAULT, model="exact", engine=None):
    """Scaled measurement rows per candidate: -dP*/dθ σ_prior / σ, shape (c, 3, k); for a 6-DoF
    platform (P (c, 6)) also the orientation rows -dφ*/dθ σ_prior / σ_rad (``SIGMA_RAD_DEFAULT``),
    shape (c, 6, k)."""
    base = model_robot(robot, model)
    if is_spatial(robot):
        data = Data(
            sample=np.arange(len(P)).astype(str),
            L=L0,
            pose=P[:, :3],
            sigma=np.full(len(P), sigma),
            encoder=False,
            source="<plan>",
            rotvec=P[:, 3:],
        )
        prob = Problem(base, data, index, sd, engine=engine)
        return prob.jacobian(np.zeros(len(index)))[: 6 * len(P)].reshape(len(P), 6, len(index))
    data = Data(
        sample=np.arange(len(P)).astype(str),
        L=L0,
        pose=P,
        sigma=np.full(len(P), sigma),
        encoder=False,
        source="<plan>",
    )
    prob = Problem(base, data, index, sd, engine=engine)
    return prob.jacobian(np.zeros(len(index)))[: 3 * len(P)].reshape(len(P), 3, len(index))


#: log det differences [-] below which two D-optimal candidates tie (broken by candidate order): a
#: symmetric robot on a symmetric candidate grid has exact ties, which round-off would otherwise break
#: differently on different CPUs (1e-9 in log det is a relative 1e-9 in the determinant).
LOGDET_TIE = 1e-9


def _first_within(values, tol):
    """Lowest index whose value lies within ``tol`` of the largest of ``values``."""
    values = np.asarray(values, dtype=float)
    return int(np.flatnonzero(values >= values.max() - tol)[0])


def d_optimal(rows, n, exchange=True):
    """Greedy D-optimal choice of n candidates maximising det(Σ J_kᵀ J_k + I), then one exchange pass.

    Each greedy step adds the candidate with the largest det(I + J_k C J_kᵀ), C the current
    posterior covariance (matrix determinant lemma); the exchange pass swaps a chosen candidate for
    an unchosen one whenever the determinant grows. Candidates within ``LOGDET_TIE`` of the best tie
    and the first in candidate order is taken, so the plan does not depend on the last bits.

    Parameters
    ----------
    rows : ndarray, shape (c, r, k)
        Scaled measurement rows of the candidates (``info_rows``; r = 3, or 6 for a 6-DoF platform).
    n : int
        Plan size (repeats allowed: a pose may be measured twice).
    exchange : bool

    Returns
    -------
    chosen : ndarray of int, shape (n,)
    logdet : float
        log det of the information matrix of the plan (prior included).

    References
    ----------
    Atkinson & Donev 1992, ch. 11 and 15.
    """
    c, nr, k = rows.shape
    info = np.eye(k)
    chosen = []
    for _ in range(n):
        C = np.linalg.inv(info)
        M = np.eye(nr) + np.einsum("cik,kl,cjl->cij", rows, C, rows)
        j = _first_within(np.linalg.slogdet(M)[1], LOGDET_TIE)
        chosen.append(j)
        info += rows[j].T @ rows[j]
    chosen = np.array(chosen)
    if exchange:
        for pos in range(n):
            rest = info - rows[chosen[pos]].T @ rows[chosen[pos]]
            C = np.linalg.inv(rest)
            M = np.eye(nr) + np.einsum("cik,kl,cjl->cij", rows, C, rows)
            j = _first_within(np.linalg.slogdet(M)[1], LOGDET_TIE)
            chosen[pos] = j
            info = rest + rows[j].T @ rows[j]
    return chosen, float(np.linalg.slogdet(info)[1])


def plan_sd(rows, chosen):
    """Posterior-to-prior sd ratios of a plan: sqrt diag (Σ_chosen J_kᵀ J_k + I)^-1."""
    k = rows.shape[2]
    info = np.eye(k) + np.einsum("cik,cil->kl", rows[chosen], rows[chosen])
    return np.sqrt(np.diag(np.linalg.inv(info))), float(np.linalg.slogdet(info)[1])


def plan(
    robot,
    groups,
    n,
    box=None,
    priors=None,
    sigma=SIGMA_DEFAULT,
    n_random=50,
    seed=0,
    n_axis=7,
    command="standard",
):
    """Pick n poses among admissible candidates maximising det(JᵀJ + prior) and compare with random.

    Returns
    -------
    dict
        poses (n, 3) [m] (n, 6 [m, rad] for a 6-DoF platform: position and rotation vector of the
        expected equilibrium), lengths (n, m) [m], names, sd_d_optimal, sd_random_median (k,) [SI],
        prior_sd (k,), logdet_d_optimal, logdet_random_median, n_candidates, warnings (one sentence
        per estimated group the plan cannot see: ``BLIND_RATIO``).
    """
    priors = parse_priors(None) if priors is None else priors
    index = select_groups(robot, groups)
    sd = prior_sd(robot, index, priors)

    box = default_box(robot) if box is None else check_box(box).tolist()
    check_command(command, robot)
    P, L0 = candidates(robot, box, n_axis, command=command)
    if len(P) == 0:
        raise CdprError(f"no admissible candidate pose in the box {box}")
    rows = info_rows(robot, P, L0, index, sd, sigma)
    chosen, logdet = d_optimal(rows, n)
    rng = np.random.default_rng(seed)
    rand = [plan_sd(rows, rng.choice(len(P), n, replace=len(P) < n)) for _ in range(n_random)]
    ratio, _ = plan_sd(rows, chosen)
    of, _ = calibration_groups(robot)
    blind = [
        g
        for g in dict.fromkeys(of[k] for k in index)
        if all(ratio[i] >= BLIND_RATIO for i, k in enumerate(index) if of[k] == g)
    ]
    warnings = [
        f"the plan cannot see group {g!r}: every parameter of it keeps at least {BLIND_RATIO:.0%} of its prior sd "
        "(widen the box or the orientations, or fix the group at its prior)"
        for g in blind
    ]
    return {
        "poses": P[chosen],
        "lengths": L0[chosen],
        "names": [calibration_names(robot)[k] for k in index],
        "sd_d_optimal": ratio * sd,
        "sd_random_median": np.median([r[0] for r in rand], axis=0) * sd,
        "prior_sd": sd,
        "logdet_d_optimal": logdet,
        "logdet_random_median": float(np.median([r[1] for r in rand])),
        "n_candidates": len(P),
        "warnings": warnings,
    }
