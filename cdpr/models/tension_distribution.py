"""Tension distributions of a redundant CDPR: a point mass at a desired position (3 x m wrench matrix,
m >= 3 cables) and a rigid platform at a pose (6 x m, the section "At a pose of a rigid platform").

At the position P the extended model (eq. 3-5, 12) gives the wrench matrix W = [u_1 ... u_m]
(3 x m), u_i the unit vector from P toward the exit point D_i. The tensions must satisfy

    W t = w,   w = -w_ext,   T_min,i <= t_i <= T_max,i

(eq. 11). For m = 3 the solution is unique; for m > 3 it is chosen by one of

* ``closed_form`` (Pott, Bruckmann, Mikelsons 2009): t = t_m + W^+ (w - W t_m), with
  t_m = (T_min + T_max) / 2 and W^+ = W^T (W W^T)^-1: the solution closest to the middle of the
  bounds in the 2-norm, bounds ignored; infeasible when it leaves them.
* ``closed_form_improved`` (Pott 2014): while the closed form leaves the bounds, pin the cable with
  the largest violation to the bound it violates, move its force to the right-hand side and apply
  the closed form to the remaining cables; infeasible when three cables remain and still violate.
  Both closed forms take any number r of rows of W (r cables remain at the end): the r x m wrench
  matrix of a rigid platform at a pose (``pose_wrench``, r = rank(W)) as well as the point mass's 3.
* ``min_norm``: the exact minimum of |t - t_ref|_2 (t_ref = 0 by default) over W t = w and the
  bounds, a strictly convex quadratic programme. For m = 4 the null space of W is one-dimensional,
  t = t_p + lambda n with t_p = W^+ w + (I - W^+ W) t_ref, and each bound gives an interval for
  lambda: the minimum is lambda* = 0 clipped into their intersection (empty: infeasible); exact and
  vectorised. For m > 4 the optimum's active set (cables pinned at a bound) is found by enumerating
  every candidate set of at most m - 3 pinned cables, each bound side, solving the equality-
  constrained minimum of the free cables and keeping the feasible candidate of lowest objective
  (the optimum is one of them; exact and vectorised over points, 233 candidates for m = 6, at most
  ``MAX_ENUMERATED_CABLES`` cables).

Infeasible points get the status ``infeasible``; no tension is clipped. ``closed_form`` and
``closed_form_improved`` return the tensions they computed (outside the bounds where infeasible);
``min_norm`` returns NaN there (no feasible tension exists).

At a pose of a rigid platform
-----------------------------
At the pose (p, R) the extended model gives the wrench matrix W (6 x m, ``platform.wrench_matrix``:
columns [u_i ; r_i x u_i], u_i from B_i toward the exit point D_i) and the gravity wrench w_ext at
the centre of mass. A tension distribution satisfies

    W t = w,   w = -w_ext,   T_min,i <= t_i <= T_max,i.

``min_norm_rows`` is ``tension_distribution.min_norm`` for any number r of rows: the exact minimum
of |t - t_ref|_2 over that set, found in the null space of W (t = t* + Z lambda, t* the solution
closest to t_ref) by enumerating every active set of at most m - rank(W) cables pinned at a bound
(the optimum of this strictly convex quadratic programme is one of them). For b_i = 0 the
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
Paty et al. 2021, eq. (11)-(12):
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263.

A. Pott, T. Bruckmann, L. Mikelsons, "Closed-form force distribution for parallel wire robots",
Computational Kinematics, Springer 2009, pp. 25-34.

A. Pott, "An improved force distribution algorithm for over-constrained cable-driven parallel
robots", Computational Kinematics, Mechanisms and Machine Science 15, Springer 2014, pp. 139-146.

A. Pott, Cable-Driven Parallel Robots: Theory and Application, Springer 2018, ch. 3 (force
distribution).

Pott, A. (2018). Cable-Driven Parallel Robots: Theory and Application. Springer, ch. 3 (force
distribution as a quadratic programme).

Pott, A., Bruckmann, T., Mikelsons, L. (2009). Closed-form force distribution for parallel wire
robots. Computational Kinematics, Springer, pp. 25-34 (the closed form).

Pott, A. (2014). An improved force distribution algorithm for over-constrained cable-driven
parallel robots. Computational Kinematics, Mechanisms and Machine Science 15, Springer,
pp. 139-146 (the improved closed form).
"""

from __future__ import annotations

import functools
import itertools

import numpy as np

from cdpr.models.inverse import pose_state
from cdpr.models.platform import external_wrench, pose_arrays
from cdpr.models.platform import wrench_matrix as pose_wrench_matrix
from cdpr.models.pulleys import total_length_and_direction
from cdpr.models.statics import inverse3

METHODS = ("closed_form", "closed_form_improved", "min_norm")
DIST_STATUSES = ("ok", "infeasible")
#: Tolerance [N] on the tension bounds when checking feasibility.
FEAS_TOL = 1e-6
#: Default lowest tension [N]: a small positive minimum keeps every cable taut (and the robot stiff).
T_MIN_DEFAULT = 100.0
#: Largest m for the enumeration of active sets in ``min_norm`` (3489 candidates at m = 8).
MAX_ENUMERATED_CABLES = 8


def wrench_matrix(robot, P):
    """Wrench matrix W = [u_1 ... u_m] of the extended model at P (eq. 12).

    Parameters
    ----------
    robot : Robot
    P : array_like, shape (N, 3) [m]

    Returns
    -------
    W : ndarray, shape (N, 3, m) [-]
        Column i is the unit vector from P toward the exit point D_i.
    """
    P = np.atleast_2d(np.asarray(P, dtype=float))
    g = total_length_and_direction(P, robot.A, robot.kind, robot.h, robot.r_p, robot.d, robot.inward)
    return np.swapaxes(g.u, -1, -2)


#: Relative singular-value cut [-] under which a wrench matrix of r != 3 rows counts as of rank < r
#: (``pseudo_inverse``).
RANK_RCOND = 1e-10


def pseudo_inverse(W):
    """W^+ = W^T (W W^T)^-1, shape (N, m, r); NaN where W W^T is singular (W of rank < r).

    The Moore-Penrose pseudo-inverse of a full-row-rank wrench matrix (Paty 2021 eq. 11-12 for the
    point mass, r = 3; the r x m matrix of a rigid platform, ``pose_wrench``), as used by the
    closed-form distribution (Pott, Bruckmann, Mikelsons 2009). For r = 3 the 3 x 3 inverse is
    ``statics.inverse3``'s (NaN where |det| < ``statics.DET_EPS``); for any other r, W counts as
    singular where r > m or its smallest singular value is below ``RANK_RCOND`` times its largest.

    .. math:: W^+ = W^T (W W^T)^{-1}

    Parameters
    ----------
    W : ndarray (N, r, m) [-, m]
        Wrench matrices (``wrench_matrix`` or ``pose_wrench``; zeroed columns are
        allowed).

    Returns
    -------
    W_pinv : ndarray (N, m, r) [-, 1/m]
        W^+, with W W^+ = I where W has rank r.

    References
    ----------
    Pott, Bruckmann, Mikelsons 2009, eq. (9).
    """
    G = W @ np.swapaxes(W, -1, -2)
    n, r, m = W.shape
    if r == 3:
        inv, _ = inverse3(G)
        return np.swapaxes(W, -1, -2) @ inv
    inv = np.full_like(G, np.nan)
    if m >= r:
        sv = np.linalg.svd(np.where(np.isfinite(W), W, 0.0), compute_uv=False)
        ok = np.isfinite(W).all(axis=(1, 2)) & (sv[:, -1] > RANK_RCOND * sv[:, 0])
        inv[ok] = np.linalg.inv(G[ok])
    return np.swapaxes(W, -1, -2) @ inv


def _bounds(W, t_min, t_max):
    n, m = W.shape[0], W.shape[-1]
    lo = np.broadcast_to(np.asarray(t_min, dtype=float), (n, m))
    hi = np.broadcast_to(np.asarray(t_max, dtype=float), (n, m))
    return lo, hi


def _within(t, lo, hi):
    return np.isfinite(t).all(axis=-1) & (t >= lo - FEAS_TOL).all(axis=-1) & (t <= hi + FEAS_TOL).all(axis=-1)


def closed_form(W, w, t_min, t_max):
    """Pott's closed-form force distribution t = t_m + W^+ (w - W t_m), t_m = (T_min + T_max)/2.

    .. math:: \\mathbf t = \\mathbf t_m + \\mathbf W^+ (\\mathbf w - \\mathbf W \\mathbf t_m),\\qquad
        \\mathbf W^+ = \\mathbf W^T (\\mathbf W \\mathbf W^T)^{-1}

    Any number r of rows: the 3 force rows of a point mass (``wrench_matrix``) or the r = rank(W)
    rows of a rigid platform's wrench matrix (``pose_wrench``, 6 rows, 3 when b_i = 0).

    Parameters
    ----------
    W : ndarray, shape (N, r, m) [-, m]
        Wrench matrix (``wrench_matrix``; ``pose_wrench`` reduced to its rank).
    w : array_like, shape (N, r) or (r,) [N, N m]
        Wrench the cables must produce, -w_ext.
    t_min, t_max : array_like, shape (m,) or (N, m) [N]
        Tension bounds.

    Returns
    -------
    t : ndarray, shape (N, m) [N]
        The closed-form tensions (not clipped; NaN where W has rank < r).
    feasible : ndarray, shape (N,) bool
        T_min <= t <= T_max (within ``FEAS_TOL``).

    References
    ----------
    Pott, Bruckmann, Mikelsons 2009, eq. (9).
    """
    lo, hi = _bounds(W, t_min, t_max)
    w = np.broadcast_to(np.asarray(w, dtype=float), W.shape[:2])
    t_m = 0.5 * (lo + hi)
    r = w - np.einsum("nam,nm->na", W, t_m)
    t = t_m + np.einsum("nma,na->nm", pseudo_inverse(W), r)
    return t, _within(t, lo, hi)


def closed_form_improved(W, w, t_min, t_max):
    """Pott's improved closed form: pin the most violating cable to its bound and redistribute.

    Starting from ``closed_form``, while some free cable leaves its bounds and more than r cables
    are free (r the rows of W: 3 for a point mass, rank(W) for a rigid platform), the free cable with
    the largest violation max(T_min - t, t - T_max) is set to the bound it violates and removed;
    the closed form is applied to the free cables with the right-hand side w - sum_(pinned) t_i W_i:

    .. math:: \\mathbf t_f = \\mathbf t_{m,f} + \\mathbf W_f^+ \\Big(\\mathbf w
        - \\sum_{i\\ \\mathrm{pinned}} t_i \\mathbf W_{:,i} - \\mathbf W_f \\mathbf t_{m,f}\\Big)

    Parameters
    ----------
    W : ndarray (N, r, m) [-, m]
        Wrench matrix (``wrench_matrix``; ``pose_wrench`` reduced to its rank).
    w : array_like (N, r) or (r,) [N, N m]
        Wrench the cables must produce, -w_ext (Paty 2021 eq. 11).
    t_min, t_max : array_like (m,) or (N, m) [N]
        Tension bounds.

    Returns
    -------
    t : ndarray (N, m) [N]
        The tensions, pinned cables at their bound (outside the bounds where infeasible).
    feasible : ndarray (N,) bool
        T_min <= t <= T_max (within ``FEAS_TOL``).

    References
    ----------
    Pott 2014, section 3 (the improved closed-form method).
    """
    lo, hi = _bounds(W, t_min, t_max)
    n, m = lo.shape
    rows = W.shape[1]
    w = np.broadcast_to(np.asarray(w, dtype=float), (n, rows))
    t_m = 0.5 * (lo + hi)
    free = np.ones((n, m), dtype=bool)
    pinned = np.zeros((n, m))
    t = np.empty((n, m))
    todo = np.arange(n)
    for _ in range(m - rows + 1):
        Wf = W[todo] * free[todo][:, None, :]
        tm = np.where(free[todo], t_m[todo], 0.0)
        r = w[todo] - np.einsum("nam,nm->na", W[todo], pinned[todo]) - np.einsum("nam,nm->na", Wf, tm)
        tf = tm + np.einsum("nma,na->nm", pseudo_inverse(Wf), r)
        t[todo] = np.where(free[todo], tf, pinned[todo])
        viol = np.where(free[todo], np.maximum(lo[todo] - tf, tf - hi[todo]), -np.inf)
        worst = viol.argmax(axis=1)
        bad = viol[np.arange(len(todo)), worst] > FEAS_TOL
        can = bad & (free[todo].sum(axis=1) > rows)
        idx, col = todo[can], worst[can]
        free[idx, col] = False
        pinned[idx, col] = np.where(t[idx, col] < lo[idx, col], lo[idx, col], hi[idx, col])
        todo = todo[can]
        if todo.size == 0:
            break
    return t, _within(t, lo, hi)


def null_vector(W):
    """Null vector n of a (N, 3, 4) wrench matrix: n_i = (-1)^i det(W without column i), W n = 0;
    shape (N, 4), zero where W has rank < 3.

    Parameters
    ----------
    W : ndarray (N, 3, 4) [-]
        Wrench matrices of a 4-cable robot.

    Returns
    -------
    n : ndarray (N, 4) [-]
        A vector spanning the null space of W (not normalised).
    """
    cols = [np.delete(np.arange(4), i) for i in range(4)]
    return np.stack([(-1) ** i * np.linalg.det(W[:, :, c]) for i, c in enumerate(cols)], axis=-1)


def _min_norm_m4(W, w, lo, hi, t_ref):
    n = null_vector(W)
    Wp = pseudo_inverse(W)
    t_p = np.einsum("nma,na->nm", Wp, w - np.einsum("nam,nm->na", W, t_ref)) + t_ref  # closest to t_ref
    n2 = np.einsum("nm,nm->n", n, n)
    t_p = t_p - (np.einsum("nm,nm->n", n, t_p - t_ref) / np.where(n2 > 0, n2, 1.0))[:, None] * n
    pos, neg = n > 0, n < 0
    safe = np.where(n != 0, n, 1.0)
    a, b = (lo - t_p) / safe, (hi - t_p) / safe
    lam_lo = np.where(pos, a, np.where(neg, b, -np.inf)).max(axis=1)
    lam_hi = np.where(pos, b, np.where(neg, a, np.inf)).min(axis=1)
    fixed_ok = np.where(n == 0, (t_p >= lo - FEAS_TOL) & (t_p <= hi + FEAS_TOL), True).all(axis=1)
    feasible = fixed_ok & (lam_lo <= lam_hi) & (n2 > 0) & np.isfinite(t_p).all(axis=1)
    lam = np.clip(0.0, lam_lo, np.maximum(lam_lo, lam_hi))
    t = t_p + np.where(np.isfinite(lam), lam, 0.0)[:, None] * n
    feasible &= _within(t, lo, hi)
    return np.where(feasible[:, None], t, np.nan), feasible


def active_set_candidates(m, most=None):
    """Candidate active sets of ``min_norm`` and ``min_norm_rows``: (pinned (k, m) bool, upper
    (k, m) bool), every set of at most ``most`` (default m - 3) cables pinned at the lower or upper
    bound, the empty set first, then by size.

    Parameters
    ----------
    m : int
        Number of cables.
    most : int, optional
        Largest number of pinned cables (default m - 3: a point mass's null space).

    Returns
    -------
    pinned : ndarray (k, m) bool
        Cables pinned at a bound, one candidate per row.
    upper : ndarray (k, m) bool
        Pinned at the upper bound (else the lower), False for free cables.
    """
    pinned, upper = [], []
    for k in range((m - 3 if most is None else most) + 1):
        for cab in itertools.combinations(range(m), k):
            for side in itertools.product((False, True), repeat=k):
                p = np.zeros(m, dtype=bool)
                u = np.zeros(m, dtype=bool)
                p[list(cab)] = True
                u[[c for c, s in zip(cab, side) if s]] = True
                pinned.append(p)
                upper.append(u)
    return np.array(pinned), np.array(upper)


def _min_norm_enumerate(W, w, lo, hi, t_ref):
    n, m = lo.shape
    best = np.full(n, np.inf)
    t_best = np.full((n, m), np.nan)
    pinned_sets, upper_sets = active_set_candidates(m)
    for pin, up in zip(pinned_sets, upper_sets):
        val = np.where(up, hi, lo)
        Wf = W * ~pin
        tr = np.where(pin, 0.0, t_ref)
        r = w - np.einsum("nam,nm->na", W, np.where(pin, val, 0.0)) - np.einsum("nam,nm->na", Wf, tr)
        t = np.where(pin, val, tr + np.einsum("nma,na->nm", pseudo_inverse(Wf), r))
        resid = np.abs(np.einsum("nam,nm->na", W, t) - w).max(axis=1)
        obj = ((t - t_ref) ** 2).sum(axis=1)
        good = _within(t, lo, hi) & (resid <= FEAS_TOL) & (obj < best)
        best = np.where(good, obj, best)
        t_best[good] = t[good]
    feasible = np.isfinite(best)
    return t_best, feasible


def min_norm(W, w, t_min, t_max, t_ref=0.0, method="auto"):
    """Exact minimum of |t - t_ref|_2 subject to W t = w and T_min <= t <= T_max.

    Parameters
    ----------
    W : ndarray, shape (N, 3, m) [-]
    w : array_like, shape (N, 3) or (3,) [N]
    t_min, t_max : array_like, shape (m,) or (N, m) [N]
    t_ref : array_like, shape (m,) or (N, m) [N], optional
        Reference tensions, default 0 (the minimum 2-norm); ``t_ref`` = (T_min + T_max)/2 gives the
        bounded version of ``closed_form``.
    method : {"auto", "null_space", "enumerate"}
        ``null_space`` (m = 4 only) or ``enumerate`` (any m <= ``MAX_ENUMERATED_CABLES``); ``auto``
        takes the direct solve for m = 3, ``null_space`` for m = 4, else ``enumerate``.

    Returns
    -------
    t : ndarray, shape (N, m) [N]
        NaN where infeasible.
    feasible : ndarray, shape (N,) bool

    References
    ----------
    Pott 2018, ch. 3 (force distribution as a quadratic programme).
    """
    lo, hi = _bounds(W, t_min, t_max)
    n, m = lo.shape
    w = np.broadcast_to(np.asarray(w, dtype=float), (n, 3))
    t_ref = np.broadcast_to(np.asarray(t_ref, dtype=float), (n, m))
    if m < 3:
        raise ValueError(f"a point-mass CDPR needs at least 3 cables, got {m}")
    if method == "auto":
        method = "direct" if m == 3 else "null_space" if m == 4 else "enumerate"
    if method == "direct" or m == 3:
        t = np.einsum("nma,na->nm", pseudo_inverse(W), w)
        ok = _within(t, lo, hi)
        return np.where(ok[:, None], t, np.nan), ok
    if method == "null_space":
        if m != 4:
            raise ValueError(f"method 'null_space' needs m = 4 cables, got {m}")
        return _min_norm_m4(W, w, lo, hi, t_ref)
    if method == "enumerate":
        if m > MAX_ENUMERATED_CABLES:
            raise ValueError(
                f"min_norm enumerates active sets for at most {MAX_ENUMERATED_CABLES} cables, got {m}"
            )
        return _min_norm_enumerate(W, w, lo, hi, t_ref)
    raise ValueError(f"unknown min_norm method {method!r}; allowed: 'auto', 'null_space', 'enumerate'")


def distribute(robot, P, method="min_norm", t_min=T_MIN_DEFAULT, t_max=None, **options):
    """Tension distribution of ``robot`` holding the platform still at P (eq. 11).

    Parameters
    ----------
    robot : Robot
    P : array_like, shape (N, 3) [m]
    method : {"closed_form", "closed_form_improved", "min_norm"}
    t_min : float or array_like (m,) or (N, m) [N], default ``T_MIN_DEFAULT``
    t_max : float or array_like (m,) or (N, m) [N], optional
        Default the admissible tension T_a,i of each cable.
    options : passed to ``min_norm`` (``t_ref``, ``method`` as ``solver``).

    Returns
    -------
    dict
        t (N, m) [N]; feasible (N,) bool; status (N,) str of ``DIST_STATUSES``; W (N, 3, m).
    """
    P = np.atleast_2d(np.asarray(P, dtype=float))
    W = wrench_matrix(robot, P)
    w = -robot.platform.w_ext
    solver = options.pop("solver", "auto")
    t, ok = _distribute_rows(
        robot, W, w, t_min, t_max, method, functools.partial(min_norm, method=solver, **options)
    )
    return {"t": t, "feasible": ok, "status": np.where(ok, "ok", "infeasible"), "W": W}


def _distribute_rows(robot, W, w, t_min, t_max, method, minimum_norm):
    """The tensions t (N, m) [N] and feasible (N,) of ``distribute`` and ``distribute_pose`` from
    the wrench matrices W and the wrench w: t_max defaults to each cable's T_a, the points where W
    is not finite are infeasible (``defined_rows``), and ``method`` picks closed_form,
    closed_form_improved or min_norm (the callable ``minimum_norm(W, w, t_min, t_max)``)."""
    t_max = robot.T_a if t_max is None else t_max
    Ws, defined = defined_rows(W)
    if method == "closed_form":
        t, ok = closed_form(Ws, w, t_min, t_max)
    elif method == "closed_form_improved":
        t, ok = closed_form_improved(Ws, w, t_min, t_max)
    elif method == "min_norm":
        t, ok = minimum_norm(Ws, w, t_min, t_max)
    else:
        raise ValueError(f"unknown distribution method {method!r}; allowed: {', '.join(METHODS)}")
    return np.where(defined[:, None], t, np.nan), ok & defined


def defined_rows(W):
    """The wrench matrices with the points where W is not finite (a cable of zero length, the
    attachment at its exit point: its direction u_i = 0/0 does not exist) zeroed, and which points
    those are: the distributions then run on finite numbers (no LAPACK failure, no warning) and such
    a point is infeasible (no tension distribution exists where a cable has no direction).

    Parameters
    ----------
    W : ndarray (N, r, m) [-, m]
        Wrench matrices (``wrench_matrix`` or ``pose_wrench``).

    Returns
    -------
    W : ndarray (N, r, m) [-, m]
        W, zero at the points where it is not finite.
    defined : ndarray (N,) bool
        True where W is finite.
    """
    defined = np.isfinite(W).all(axis=(1, 2))
    return np.where(defined[:, None, None], W, 0.0), defined


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
    W = pose_wrench_matrix(u, B - p[:, None, :])
    pl = robot.platform
    w = -external_wrench(pl.mass, pl.g, robot.arrays.com, R, pl.down, pl.wrench)
    return W, w, st


def min_norm_rows(W, w, t_min, t_max, t_ref=0.0):
    """Exact minimum of |t - t_ref|_2 subject to W t = w and T_min <= t <= T_max, any row count r.

    In the null space of W: with W = U S V^T (rank k), the solutions of W t = w are
    t = t* + Z lambda, t* = t_ref + W^+ (w - W t_ref) the one closest to t_ref and Z (m x (m - k))
    the orthonormal basis of the null space (V's last m - k columns). As t* - t_ref is orthogonal
    to Z, the programme is the projection of lambda = 0 onto the polytope
    T_min <= t* + Z lambda <= T_max:

    .. math:: \\min_{\\lambda} |\\lambda|^2 \\quad\\text{s.t.}\\quad
        \\mathbf T_{min} \\le \\mathbf t^* + \\mathbf Z \\lambda \\le \\mathbf T_{max}

    whose optimum lies on a face fixed by an independent active set of at most m - k bounds. Every
    set S of at most m - k cables pinned at a bound v_S (``active_set_candidates``, each side) is
    solved at once for all points of that rank, lambda = Z_S^T (Z_S Z_S^T)^-1 (v_S - t*_S) (sets
    with dependent rows skipped: their face is also fixed by a smaller set); the feasible candidate
    of least |t - t_ref| is the optimum (exact, vectorised over points and sets; one SVD per point
    instead of one pseudo-inverse per candidate set). A point where W t = w has no solution (w
    outside the range of a rank-deficient W) is infeasible.

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
    Pott 2018, ch. 3 (force distribution as a quadratic programme); Nocedal & Wright 2006, ch. 16
    (active sets of a convex quadratic programme).
    """
    n, r, m = W.shape
    if m > MAX_CABLES:
        raise ValueError(f"min_norm_rows enumerates active sets for at most {MAX_CABLES} cables, got {m}")
    lo = np.broadcast_to(np.asarray(t_min, dtype=float), (n, m))
    hi = np.broadcast_to(np.asarray(t_max, dtype=float), (n, m))
    t_ref = np.broadcast_to(np.asarray(t_ref, dtype=float), (n, m))
    w = np.broadcast_to(np.asarray(w, dtype=float), (n, r))
    t_best = np.full((n, m), np.nan)
    if n == 0:
        return t_best, np.zeros(0, dtype=bool)
    U, s, Vt = np.linalg.svd(W)
    rank = (s > 1e-12 * s[:, :1]).sum(axis=1)
    for k in np.unique(rank):  # one group at regular poses
        pins, ups = active_set_candidates(m, m - k)
        g = np.flatnonzero(rank == k)
        step = max(1, _CANDIDATE_BUDGET // len(pins))
        for a in range(0, len(g), step):
            i = g[a : a + step]
            t_best[i] = _null_space_optimum(
                W[i], w[i], lo[i], hi[i], t_ref[i], U[i], s[i], Vt[i], k, pins, ups
            )
    return t_best, np.isfinite(t_best).all(axis=1)


#: Points x candidate sets solved at once by ``min_norm_rows`` (bounds its memory).
_CANDIDATE_BUDGET = 100_000


def _null_space_optimum(W, w, lo, hi, t_ref, U, s, Vt, k, pins, ups):
    """``min_norm_rows`` at points where W (n, r, m) = U diag(s) Vt has rank k, over the candidate
    active sets (pins, ups) (``active_set_candidates`` of at most m - k pinned cables): the optimum
    t (n, m), NaN where infeasible."""
    m = W.shape[2]
    scale = np.maximum(1.0, np.abs(w).max(axis=1))
    # t* = t_ref + V_k S_k^-1 U_k^T (w - W t_ref), the solution closest to t_ref
    coef = np.einsum("nak,na->nk", U[:, :, :k], w - np.einsum("nam,nm->na", W, t_ref)) / s[:, :k]
    t_star = t_ref + np.einsum("nkm,nk->nm", Vt[:, :k, :], coef)
    Z = np.swapaxes(Vt[:, k:, :], 1, 2)  # (n, m, d) null-space basis
    val = np.where(ups[None], hi[:, None], lo[:, None])  # (n, c, m) the pinned values
    size = pins.sum(axis=1)
    lam = np.zeros((len(W), len(pins), m - k))
    for q in range(1, size.max() + 1):
        c = np.flatnonzero(size == q)
        cols = np.nonzero(pins[c])[1].reshape(len(c), q)  # the pinned cables of each set
        b = np.take_along_axis(val[:, c], cols[None], axis=2) - t_star[:, cols]
        lam[:, c] = _least_norm_solution(Z[:, cols, :], b)
    t = np.where(pins[None], val, t_star[:, None] + np.einsum("nmd,ncd->ncm", Z, lam))
    resid = np.abs(np.einsum("nam,ncm->nca", W, t) - w[:, None]).max(axis=2)
    inside = (t >= lo[:, None] - FEAS_TOL).all(axis=2) & (t <= hi[:, None] + FEAS_TOL).all(axis=2)
    good = np.isfinite(t).all(axis=2) & inside & (resid <= 1e-9 * scale[:, None])
    obj = np.where(good, ((t - t_ref[:, None]) ** 2).sum(axis=2), np.inf)
    best = obj.argmin(axis=1)
    out = np.full((len(W), m), np.nan)
    found = np.isfinite(obj[np.arange(len(W)), best])
    out[found] = t[found, best[found]]
    return out


def _least_norm_solution(A, b):
    """The least-norm x of A x = b for stacked k x d matrices A (..., k, d) of full row rank k <= d
    and b (..., k): x = A^T (A A^T)^-1 b, the k x k system in closed form for k <= 2; NaN where
    the rows of A are dependent (Gram determinant below 1e-12 of the product of its diagonal, or
    smallest eigenvalue below 1e-12 of the largest)."""
    k = A.shape[-2]
    G = np.einsum("...kd,...jd->...kj", A, A)
    if k == 1:
        g = G[..., 0, 0]
        y = (b[..., 0] / np.where(g > 1e-24, g, np.nan))[..., None]
    elif k == 2:
        a, c, e = G[..., 0, 0], G[..., 0, 1], G[..., 1, 1]
        det = a * e - c * c
        det = np.where(det > 1e-12 * a * e, det, np.nan)
        y = np.stack([(e * b[..., 0] - c * b[..., 1]) / det, (a * b[..., 1] - c * b[..., 0]) / det], axis=-1)
    else:
        ev = np.linalg.eigvalsh(G)
        regular = ev[..., 0] > 1e-12 * ev[..., -1]
        Gs = np.where(regular[..., None, None], G, np.eye(k))
        y = np.where(regular[..., None], np.linalg.solve(Gs, b[..., None])[..., 0], np.nan)
    return np.einsum("...kd,...k->...d", A, y)


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
    t, ok = _distribute_rows(robot, W, w, t_min, t_max, method, min_norm_rows)
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
