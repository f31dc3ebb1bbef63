"""Tension distribution and compensated rest lengths of a rigid platform at a pose (6 x m wrench matrix).

At the pose (p, R) the extended model gives the wrench matrix W (6 x m, ``platform.wrench_matrix``:
columns [u_i ; r_i x u_i], u_i from B_i toward the exit point D_i) and the gravity wrench w_ext at
the centre of mass. A tension distribution satisfies

    W t = w,   w = -w_ext,   T_min,i <= t_i <= T_max,i.

``min_norm_rows`` is ``tension_distribution.min_norm`` generalised from 3 rows to any number r of
rows: the exact minimum of |t - t_ref|_2 over that set, found by enumerating every active set of
at most m - r cables pinned at a bound (the optimum of this strictly convex quadratic programme is
one of them: at most m - rank(W) constraints are active beyond the r equalities). For b_i = 0 the
6 x m matrix has rank 3: its moment rows are zero and are dropped (the point-mass case, where the
enumeration is ``tension_distribution``'s). A robot with m < rank rows (an under-constrained robot at an
arbitrary orientation) has, in general, no solution: ``infeasible``, never solved by force.

``distribute_pose`` also takes Pott's ``closed_form`` and ``closed_form_improved``
(``tension_distribution``'s functions, which work on the pseudo-inverse W^+ = W^T (W W^T)^-1 of any
row count): the rows of W are first reduced to its rank (``rank_rows``: the 3 force rows where every
b_i = 0, else all 6), so that W W^T is regular wherever the robot can hold the pose.

Compensation: the rest lengths that bring the platform to the pose under the distribution t are,
by Hooke's law (Paty 2021 eq. 10, 13), L0_i = L_TE,i / (1 + t_i / (E_i S_i)).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (eq. 10-13).

Pott, A. (2018). Cable-Driven Parallel Robots: Theory and Application. Springer, ch. 3 (force
distribution as a quadratic programme).

Pott, A., Bruckmann, T., Mikelsons, L. (2009). Closed-form force distribution for parallel wire
robots. Computational Kinematics, Springer, pp. 25-34 (the closed form).

Pott, A. (2014). An improved force distribution algorithm for over-constrained cable-driven
parallel robots. Computational Kinematics, Mechanisms and Machine Science 15, Springer,
pp. 139-146 (the improved closed form).
"""

from __future__ import annotations

import itertools

import numpy as np

from cdpr.models.inverse import pose_state
from cdpr.models.platform import external_wrench, pose_arrays, wrench_matrix
from cdpr.models.tension_distribution import (
    FEAS_TOL,
    METHODS,
    T_MIN_DEFAULT,
    closed_form,
    closed_form_improved,
)

#: Cables up to which the active sets are enumerated.
MAX_CABLES = 12


def pose_wrench(robot, p, R):
    """Wrench matrix W (N, 6, m) of the extended model at poses and the wrench w = -w_ext (N, 6).

    Parameters
    ----------
    robot : Robot
    p : ndarray (N, 3) [m]
        Reference points.
    R : ndarray (N, 3, 3) [-]
        Orientations.

    Returns
    -------
    W : ndarray (N, 6, m) [-, m]
    w : ndarray (N, 6) [N, N m]
    state : PulleyState
        The extended model at the attachment points (L_TE (N, m) [m]).

    References
    ----------
    Paty et al. 2021, eq. (11)-(12); Pott 2018, eq. (3.31).
    """
    B, st = pose_state(robot, p, R)
    u = st.D - B
    u = u / np.linalg.norm(u, axis=-1, keepdims=True)
    W = wrench_matrix(u, B - p[:, None, :])
    w = -external_wrench(robot.platform.mass, robot.platform.g, robot.arrays.com, R, robot.platform.down)
    return W, w, st


def min_norm_rows(W, w, t_min, t_max, t_ref=0.0):
    """Exact minimum of |t - t_ref|_2 subject to W t = w and T_min <= t <= T_max, any row count r.

    Parameters
    ----------
    W : ndarray (N, r, m) [-]
        Wrench matrices.
    w : ndarray (N, r) [N]
        Wrenches to produce.
    t_min, t_max : array_like (m,) or (N, m) [N]
        Bounds.
    t_ref : array_like (m,) or (N, m) [N], optional
        Reference tensions (default 0, the least 2-norm).

    Returns
    -------
    t : ndarray (N, m) [N]
        NaN where infeasible.
    feasible : ndarray (N,) bool

    References
    ----------
    Pott 2018, ch. 3 (force distribution as a quadratic programme).
    """
    n, r, m = W.shape
    if m > MAX_CABLES:
        raise ValueError(f"min_norm_rows enumerates active sets for at most {MAX_CABLES} cables, got {m}")
    lo = np.broadcast_to(np.asarray(t_min, dtype=float), (n, m))
    hi = np.broadcast_to(np.asarray(t_max, dtype=float), (n, m))
    t_ref = np.broadcast_to(np.asarray(t_ref, dtype=float), (n, m))
    best = np.full(n, np.inf)
    t_best = np.full((n, m), np.nan)
    scale = np.maximum(1.0, np.abs(w).max(axis=1))
    for k in range(max(m - r, 0) + 1):
        for cab in itertools.combinations(range(m), k):
            for side in itertools.product((False, True), repeat=k):
                pin = np.zeros(m, dtype=bool)
                up = np.zeros(m, dtype=bool)
                pin[list(cab)] = True
                up[[c for c, s in zip(cab, side) if s]] = True
                val = np.where(up, hi, lo)
                Wf = W * ~pin
                tr = np.where(pin, 0.0, t_ref)
                rhs = (
                    w - np.einsum("nam,nm->na", W, np.where(pin, val, 0.0)) - np.einsum("nam,nm->na", Wf, tr)
                )
                t = np.where(pin, val, tr + np.einsum("nma,na->nm", np.linalg.pinv(Wf, rcond=1e-12), rhs))
                resid = np.abs(np.einsum("nam,nm->na", W, t) - w).max(axis=1)
                obj = ((t - t_ref) ** 2).sum(axis=1)
                inside = (t >= lo - FEAS_TOL).all(axis=1) & (t <= hi + FEAS_TOL).all(axis=1)
                good = np.isfinite(t).all(axis=1) & inside & (resid <= 1e-9 * scale) & (obj < best)
                best = np.where(good, obj, best)
                t_best[good] = t[good]
    return t_best, np.isfinite(best)


def rank_rows(robot, W, w):
    """The rows of the wrench matrix and wrench that its rank keeps: the 3 force rows of a platform
    with every b_i = 0 and c = 0 (its moment rows vanish: rank 3), all 6 rows otherwise.

    Parameters
    ----------
    robot : Robot
    W : ndarray (N, 6, m) [-, m]
        Wrench matrices (``pose_wrench``).
    w : ndarray (N, 6) [N, N m]
        Wrenches to produce.

    Returns
    -------
    W : ndarray (N, r, m) [-, m]
    w : ndarray (N, r) [N, N m]
        r = 3 (point-mass platform) or 6.
    """
    if robot.point_mass:  # rank 3: the moment rows are zero
        return W[:, :3], w[:, :3]
    return W, w


def distribute_pose(robot, p, rotvec=None, t_min=T_MIN_DEFAULT, t_max=None, method="min_norm"):
    """Tension distribution holding the platform still at poses (wrench feasibility): the minimum
    norm in the bounds (default), or Pott's closed form or improved closed form on the rows of W
    that its rank keeps (``rank_rows``).

    .. math:: \\mathbf W \\mathbf t = -\\mathbf w_{ext},\\qquad T_{min,i} \\le t_i \\le T_{max,i}

    Parameters
    ----------
    robot : Robot
    p : array_like (N, 3) or (N, 6) [m, rad]
        Positions or poses.
    rotvec : array_like (N, 3) or (3,) [rad], optional
        Orientations (default identity).
    t_min : float or array_like (m,) [N]
        Least tension (default ``tension_distribution.T_MIN_DEFAULT``).
    t_max : float or array_like (m,) [N], optional
        Largest tension (default each cable's T_a).
    method : {"min_norm", "closed_form", "closed_form_improved"}
        ``min_norm_rows``, ``tension_distribution.closed_form`` or
        ``tension_distribution.closed_form_improved``.

    Returns
    -------
    dict
        t (N, m) [N] (min_norm: NaN where infeasible; the closed forms: the tensions they computed,
        outside the bounds where infeasible, NaN where W has rank < r), feasible (N,), status (N,)
        'ok' | 'infeasible', W (N, r, m) (r = 6, or 3 for a point-mass platform), L_TE (N, m) [m],
        p (N, 3), R (N, 3, 3).

    References
    ----------
    Paty et al. 2021, eq. (11)-(12); Pott 2018, ch. 3; Pott, Bruckmann, Mikelsons 2009, eq. (9);
    Pott 2014, section 3.
    """
    if method not in METHODS:
        raise ValueError(f"unknown distribution method {method!r}; allowed: {', '.join(METHODS)}")
    p, R = pose_arrays(p, rotvec)
    W, w, st = pose_wrench(robot, p, R)
    W, w = rank_rows(robot, W, w)
    t_max = robot.T_a if t_max is None else t_max
    if method == "closed_form":
        t, ok = closed_form(W, w, t_min, t_max)
    elif method == "closed_form_improved":
        t, ok = closed_form_improved(W, w, t_min, t_max)
    else:
        t, ok = min_norm_rows(W, w, t_min, t_max)
    return {
        "t": t,
        "feasible": ok,
        "status": np.where(ok, "ok", "infeasible"),
        "W": W,
        "L_TE": st.L_TE,
        "p": p,
        "R": R,
    }


def compensated_lengths(robot, p, rotvec=None, t_min=T_MIN_DEFAULT, t_max=None, method="min_norm"):
    """Rest lengths that bring the platform to the pose under the tension distribution t
    (``distribute_pose``), L0_i = L_TE,i / (1 + t_i / (E_i S_i)).

    .. math:: L_{0,i} = \\frac{L_{TE,i}}{1 + t_i / (E_i S_i)}

    Parameters
    ----------
    robot : Robot
    p : array_like (N, 3) or (N, 6) [m, rad]
        Positions or poses.
    rotvec : array_like (N, 3) or (3,) [rad], optional
        Orientations (default identity).
    t_min : float or array_like (m,) [N]
        Least tension.
    t_max : float or array_like (m,) [N], optional
        Largest tension (default T_a).
    method : {"min_norm", "closed_form", "closed_form_improved"}
        The distribution (``distribute_pose``).

    Returns
    -------
    dict
        ``distribute_pose``'s keys and L0 (N, m) [m] (NaN where infeasible).

    References
    ----------
    Paty et al. 2021, eq. (10), (13).
    """
    out = distribute_pose(robot, p, rotvec, t_min, t_max, method)
    L0 = out["L_TE"] / (1.0 + out["t"] / robot.ES)
    out["L0"] = np.where(out["feasible"][:, None], L0, np.nan)
    return out
