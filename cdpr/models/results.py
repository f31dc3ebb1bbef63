"""What a solved point is, in both redundancy modes: the statuses and the per-point columns.

Paper mode (``subsets``) and physical mode (``equilibrium``), numpy or compiled, return dicts of
arrays with the same core keys; the tables built from them (``cdpr.tables.to_frame``) start with the
same columns (``pose_columns``) and label the cables that hold the platform the same way
(``subset_codes`` in paper mode, ``taut_labels`` in physical mode). No pandas here: labels are
integer codes into a list of categories, which ``to_frame`` turns into categoricals.

Status of a point (``STATUSES``):
  ok             an admissible subset exists (paper) / the forces balance with 0 <= t <= T_a (physical);
  over_tension   a cable would need more than its admissible tension T_a;
  slack          the cables would need a negative (pushing) tension;
  not_converged  the solver hit its iteration cap;
  inaccessible   no geometric solution (spheres do not meet, point above the pulleys or outside the
                 anchors, point inside a sheave, coplanar cables).
  out_of_frame   a pose was solved (it would be ok or over_tension) but its reference point P* lies
                 more than ``FRAME_TOL`` outside the frame box (``frame_bounds``: the anchors'
                 bounding box extended down to the floor), e.g. a rigid platform on too few cables
                 hanging below the floor (``mark_out_of_frame``).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (eq. 14, section 3.2).
"""

from __future__ import annotations

import numpy as np

STATUSES = ("ok", "slack", "over_tension", "inaccessible", "not_converged", "out_of_frame")

#: The default floor of a suspended robot [m] (``Robot.floor_z``: the robot file's
#: ``frame.floor_z_m``, 0 by default when every anchor lies above it); the platform hangs between it
#: and the pulleys.
FLOOR_Z = 0.0


def mark_below_floor(res, p, floor_z=FLOOR_Z):
    """Mark the desired points below the floor (z < ``floor_z``) of a suspended point-mass robot
    ``inaccessible`` in a solver's per-point result, whatever the solver found there: one rule for every command and engine (a
    point under the floor cannot be reached, even where the cable model has an equilibrium).

    Parameters
    ----------
    res : dict
        Per-point arrays of a solver (``status`` and, if present, ``status_code``), changed in place.
    p : array_like, shape (N, 3) [m]
        The desired points.
    floor_z : float [m]
        Height of the robot's floor (``Robot.floor_z``).

    Returns
    -------
    dict
        ``res``.
    """
    below = np.asarray(p, dtype=float).reshape(-1, 3)[:, 2] < floor_z
    if below.any():
        if "status_code" in res:
            res["status_code"] = np.where(below, STATUSES.index("inaccessible"), res["status_code"]).astype(
                np.asarray(res["status_code"]).dtype
            )
        res["status"] = np.where(below, "inaccessible", np.asarray(res["status"]).astype(str))
    return res


#: How far [m] a solved reference point P* may lie outside the frame box (``frame_bounds``) and still
#: count as inside it; beyond it the point is ``out_of_frame`` (``mark_out_of_frame``).
FRAME_TOL = 1e-3


def frame_bounds(robot):
    """The frame box of a robot: the bounding box of its anchors (joint points A) extended down to
    its floor (``Robot.floor_z``).

    Parameters
    ----------
    robot : Robot
        Supplies the joint points A (m, 3) [m] and the floor height [m].

    Returns
    -------
    lo, hi : ndarray (3,) [m]
        Lower and upper corners: x, y, z of the anchors' minimum (z: the lower of the floor and the
        lowest anchor) and maximum.
    """
    A = np.asarray(robot.A, dtype=float)
    lo = A.min(axis=0)
    lo[2] = min(float(lo[2]), float(robot.floor_z))
    return lo, A.max(axis=0)


def mark_out_of_frame(res, robot, tol=FRAME_TOL):
    """Mark the solved poses whose reference point P* lies more than ``tol`` outside the robot's
    frame box (``frame_bounds``) ``out_of_frame`` in a solver's per-point result: only points that
    are ``ok`` or ``over_tension`` change (a pose was found, but not one the robot can hold inside
    its frame). One rule for every command and engine of physical mode (``cdpr.solve``; paper mode
    follows the paper, which evaluates every point of its volume). The box is the file's: axes with
    gravity along -z; a robot whose gravity is turned (``Platform.down`` not -z, e.g. a whole robot
    rotated to test invariance) has no such box and is not marked.

    Parameters
    ----------
    res : dict
        Per-point arrays of a solver (``P_s``, ``status`` and, if present, ``status_code``),
        changed in place.
    robot : Robot
        Supplies the frame box.
    tol : float [m]
        Distance outside the box tolerated as inside.

    Returns
    -------
    dict
        ``res``.
    """
    if "P_s" not in res or "status" not in res:
        return res
    if tuple(robot.platform.down) != (0.0, 0.0, -1.0):
        return res  # a robot turned with its gravity (an invariance test): no box in the file's axes
    P = np.asarray(res["P_s"], dtype=float).reshape(-1, 3)
    if not len(P):
        return res
    lo, hi = frame_bounds(robot)
    with np.errstate(invalid="ignore"):
        outside = ((P < lo - tol) | (P > hi + tol)).any(axis=1)
    status = np.asarray(res["status"]).astype(str)
    hit = outside & np.isin(status, ("ok", "over_tension"))
    if hit.any():
        if "status_code" in res:
            res["status_code"] = np.where(hit, STATUSES.index("out_of_frame"), res["status_code"]).astype(
                np.asarray(res["status_code"]).dtype
            )
        res["status"] = np.where(hit, "out_of_frame", status)
    return res


def subset_label(subset_row):
    """1-based cable numbers joined by '-', e.g. '1-2-3'; '' when no subset.

    Parameters
    ----------
    subset_row : sequence of 3 int
        0-based cable indices of a subset (a row of ``solve_points``' ``subset``); a negative first
        entry means no subset.

    Returns
    -------
    label : str
        The label, e.g. '1-2-3', or '' when there is no subset.
    """
    if subset_row[0] < 0:
        return ""
    return "-".join(str(int(i) + 1) for i in subset_row)


def subset_codes(robot, subset):
    """Codes and categories of the subset labels ('1-2-3', ..., '' when none) of an (N, 3) array of
    0-based subsets (no Python loop per point).

    Parameters
    ----------
    robot : Robot
        Supplies m and ``subsets`` (n_subsets, 3), in lexicographic order.
    subset : array_like (N, 3) int
        0-based cables of each point's subset, -1 when none.

    Returns
    -------
    codes : ndarray (N,) int
        Index into ``labels``.
    labels : list of str, length n_subsets + 1
        ``subset_label`` of every subset, then ''.
    """
    subs = robot.subsets
    labels = [subset_label(s) for s in subs] + [""]
    weights = np.array([robot.m * robot.m, robot.m, 1])
    skey = subs @ weights  # lexicographic order -> sorted keys
    rows = np.asarray(subset).reshape(-1, 3)
    key = rows @ weights
    pos = np.minimum(np.searchsorted(skey, key), len(subs) - 1)
    code = np.where((rows[:, 0] >= 0) & (skey[pos] == key), pos, len(subs))
    return code, labels


def taut_labels(taut):
    """Codes and categories of the taut cables' labels, 1-based numbers joined by '-' ('1-2-4'; ''
    none), from a (N, m) bool array (codes from the bit pattern; no Python loop per point).

    Parameters
    ----------
    taut : array_like (N, m) bool
        Taut cables per point.

    Returns
    -------
    codes : ndarray (N,) int64
        Index into ``labels``: the bit pattern of the taut cables.
    labels : list of str, length 2^m
        All cable sets.
    """
    taut = np.asarray(taut, dtype=bool)
    m = taut.shape[1]
    code = taut.astype(np.int64) @ (1 << np.arange(m))
    labels = ["-".join(str(i + 1) for i in range(m) if c >> i & 1) for c in range(1 << m)]
    return code, labels


def pose_columns(robot, res):
    """The columns every per-point table starts with, from a solver result ``res`` (paper or
    physical mode): x, y, z (desired P), x_s, y_s, z_s (solved P*) [m], dp = |P* - P| (Paty 2021
    eq. 14) [m], t1..tm [N] (NaN where slack).

    Parameters
    ----------
    robot : Robot
        Supplies the number of cables m.
    res : dict
        Arrays p (N, 3), P_s (N, 3), dp (N,), t (N, m).

    Returns
    -------
    dict
        Column name -> (N,) array, in table order: x, y, z, x_s, y_s, z_s, dp, t1..tm.
    """
    cols = {
        "x": res["p"][:, 0],
        "y": res["p"][:, 1],
        "z": res["p"][:, 2],
        "x_s": res["P_s"][:, 0],
        "y_s": res["P_s"][:, 1],
        "z_s": res["P_s"][:, 2],
        "dp": res["dp"],
    }
    cols.update({f"t{i + 1}": res["t"][:, i] for i in range(robot.m)})
    return cols


#: A cable counts as taut when its tension exceeds this [N]: below it, the tension is the round-off
#: of a cable resting at exactly its rest length (stretch ~1e-16 m).
TAUT_MIN = 1e-6
#: Distance [m] outside the anchors' horizontal convex hull tolerated as inside.
HULL_EPS = 1e-9
#: Index of each status in ``STATUSES``.
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


def physical_result(robot, p, P, t, residual, iters, conv, inside, halfplanes=None):
    """The result dict of a point mass's physical solve (``POINT_KEYS``) from the solved arrays (the compiled engines build
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


#: The keys of a point mass's physical-mode result (``physical_result``).
POINT_KEYS = (
    "p", "P_s", "dp", "t", "taut", "n_taut", "residual", "iterations", "converged", "status_code", "status",
)  # fmt: skip


def point_keys(res):
    """The point-mass keys (``POINT_KEYS``) of a physical-mode result of ``equilibrium.solve``: what
    both engines return for a suspended point mass solved without an orientation.

    Parameters
    ----------
    res : dict
        A result of ``equilibrium.solve`` (or of the compiled engine).

    Returns
    -------
    dict
        The same arrays under ``POINT_KEYS``.
    """
    return {k: res[k] for k in POINT_KEYS}


def ok_point_sensitivities(res, names, at, t_tol, cond_max):
    """The dict of a ``sensitivities_at`` (massless or heavy): S, margin_t and cond computed by
    ``at`` on the ok points of ``res`` only (NaN, NaN and inf elsewhere), and where they are smooth.

    Parameters
    ----------
    res : dict
        A physical-mode result (P_s (N, 3) [m], status (N,)).
    names : list of str
        The parameters, one column of S each.
    at : callable
        ``at(idx)`` -> S (n, 6, len(names)), margin_t (n,) [N], cond (n,) at the ok points idx (n,).
    t_tol : float [N]
        Tension margin under which a point is not smooth.
    cond_max : float
        Scaled condition number at and above which a point is not smooth.

    Returns
    -------
    dict
        names; S (N, 6, len(names)); smooth (N,) bool: ok, margin_t > ``t_tol`` and cond <
        ``cond_max``; margin_t (N,) [N]; cond (N,).
    """
    n = len(res["P_s"])
    S = np.full((n, 6, len(names)), np.nan)
    margin = np.full(n, np.nan)
    cond = np.full(n, np.inf)
    ok = np.asarray(res["status"]) == "ok"
    idx = np.flatnonzero(ok)
    if idx.size:
        S[idx], margin[idx], cond[idx] = at(idx)
    smooth = ok & (margin > t_tol) & (cond < cond_max)
    return {"names": names, "S": S, "smooth": smooth, "margin_t": margin, "cond": cond}
