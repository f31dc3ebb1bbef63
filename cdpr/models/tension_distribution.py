"""Tension distribution of a redundant point-mass CDPR at a desired position (m >= 3 cables).

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
  matrix of a rigid platform at a pose (``distribution6``, r = rank(W)) as well as the point mass's 3.
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
"""

from __future__ import annotations

import itertools

import numpy as np

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
    point mass, r = 3; the r x m matrix of a rigid platform, ``distribution6``), as used by the
    closed-form distribution (Pott, Bruckmann, Mikelsons 2009). For r = 3 the 3 x 3 inverse is
    ``statics.inverse3``'s (NaN where |det| < ``statics.DET_EPS``); for any other r, W counts as
    singular where r > m or its smallest singular value is below ``RANK_RCOND`` times its largest.

    .. math:: W^+ = W^T (W W^T)^{-1}

    Parameters
    ----------
    W : ndarray (N, r, m) [-, m]
        Wrench matrices (``wrench_matrix`` or ``distribution6.pose_wrench``; zeroed columns are
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
    rows of a rigid platform's wrench matrix (``distribution6``, 6 rows, 3 when b_i = 0).

    Parameters
    ----------
    W : ndarray, shape (N, r, m) [-, m]
        Wrench matrix (``wrench_matrix``; ``distribution6.pose_wrench`` reduced to its rank).
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
        Wrench matrix (``wrench_matrix``; ``distribution6.pose_wrench`` reduced to its rank).
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


def active_set_candidates(m):
    """Candidate active sets of ``min_norm``: (pinned (k, m) bool, upper (k, m) bool), every set of
    at most m - 3 cables pinned at the lower or upper bound, the empty set first.

    Parameters
    ----------
    m : int
        Number of cables.

    Returns
    -------
    pinned : ndarray (k, m) bool
        Cables pinned at a bound, one candidate per row.
    upper : ndarray (k, m) bool
        Pinned at the upper bound (else the lower), False for free cables.
    """
    pinned, upper = [], []
    for k in range(m - 2):
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
    t_max = robot.T_a if t_max is None else t_max
    if method == "closed_form":
        t, ok = closed_form(W, w, t_min, t_max)
    elif method == "closed_form_improved":
        t, ok = closed_form_improved(W, w, t_min, t_max)
    elif method == "min_norm":
        solver = options.pop("solver", "auto")
        t, ok = min_norm(W, w, t_min, t_max, method=solver, **options)
    else:
        raise ValueError(f"unknown distribution method {method!r}; allowed: {', '.join(METHODS)}")
    return {"t": t, "feasible": ok, "status": np.where(ok, "ok", "infeasible"), "W": W}
