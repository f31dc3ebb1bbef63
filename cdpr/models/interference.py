"""Interference of the cables with each other and with the platform body, at poses.

Cable i's free span is the straight segment P_i(s) = B_i + s (D_i - B_i), s in [0, 1], from its
attachment point B_i = p + R b_i (s = 0) to its sheave exit point D_i (s = 1; the tangent point D of
``pulleys.pulley_state``, Paty 2021 eq. 3-7; D_i = A_i for a fixed pulley). Its radius is ``cable.diameter_m`` / 2.

* **Cable-cable**: the exact distance between two segments (``segment_distance``, Ericson 2005
  section 5.1.9: crossing, parallel, collinear and zero-length segments); the pair i < j interferes
  iff d_ij < r_i + r_j. Pairs that share an end point by construction (the same attachment
  b_i = b_j, at ``B``, or two fixed pulleys at the same A, at ``D``) are not tested but listed as
  shared; on a point mass every pair meets at P, so it never has cable-cable interference.
* **Cable-platform**: the platform body is a convex polytope in the platform frame, the half-spaces
  n_k . x + o_k <= 0 (``platform_faces``): the convex hull of the attachments (``platform.body:
  hull``, the default; none when they span no volume), a box, or none. The segment (its centre line:
  the cable's radius plays no part here) is clipped exactly by the faces (Cyrus-Beck,
  ``clip_segments``); it interferes when one of its points lies deeper than ``DEPTH_TOL`` inside the
  body, so a cable that touches a face, an edge or a vertex (its own attachment) does not. The chord
  inside is [s_in, s_out], its length (s_out - s_in) |D_i - B_i| and its depth the largest distance
  of a chord point to the body's boundary.

Heavy cables (``cable.linear_density_kg_m`` > 0, issue 38) sag: the span is then the polyline of
``POLYLINE_PIECES`` straight pieces through the points of Irvine's elastic catenary at equal steps of
unstrained arc length (``catenary.shape``) from B_i to the exit point D_i of the heavy pulley
coupling (``cables.HeavyCables.exit_points``), under the cable's rest length L0_i (given with the
pose: the catenary depends on the tension, not on the pose alone). The tests run on its pieces: the
pair distance is the smallest segment-segment distance over the pieces' pairs, the chord inside the
body the union of the pieces' clipped chords; s is then the fraction of the free span's unstrained
length (the pieces' junctions are at s = k / K). A straight cable is the polyline of one piece (the
same code), and w -> 0 is continuous: the catenary's points then lie on the chord. The polyline is
within about f / K^2 of the curve (f the cable's sag, K the pieces: the sagitta of a parabola's
piece).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (the exit point D).

Ericson, C. (2005). Real-Time Collision Detection. Morgan Kaufmann, section 5.1.9 (closest points
of two segments) and section 5.3.8 (intersecting a segment against a convex polyhedron).

Cyrus, M., Beck, J. (1978). Generalized two- and three-dimensional clipping. Computers & Graphics
3(1), 23-28.

Lumelsky, V. J. (1985). On fast computation of distance between line segments. Information
Processing Letters 21(2), 55-61.
"""

from __future__ import annotations

import itertools
from typing import NamedTuple

import numpy as np

from cdpr.errors import CdprError
from cdpr.models.cables import HeavyCables
from cdpr.models.catenary import shape
from cdpr.models.inverse import pose_state
from cdpr.models.platform import pose_arrays
from cdpr.robot import BoxBody

#: Depth [m] beyond which a point of a cable's segment counts as inside the platform body.
DEPTH_TOL = 1e-9
#: Squared length [m^2] under which a segment is a point (Ericson's EPSILON).
POINT_EPS = 1e-30
#: Segments whose chord depth is computed at a time, and poses per block of ``interference``
#: (bound the memory of the pairwise candidates: about DEPTH_BLOCK F^2 and POSE_BLOCK m^2 numbers).
DEPTH_BLOCK = 4096
POSE_BLOCK = 4096
#: Distance [m] under which two attachments b_i, b_j or two fixed anchors A_i, A_j are the same point
#: (the robot file's duplicate check uses the same tolerance).
SAME_POINT_M = 1e-9
#: Straight pieces of a heavy cable's polyline (``cable_polylines``): within about sag / K^2 of the
#: catenary (0.24 mm for a 1 m sag).
POLYLINE_PIECES = 64
#: The heavy cables' state ``cable_polylines`` draws from (``cables.heavy_cables``' keys).
CABLE_STATE = ("D", "H", "V_B", "L0_free")
#: Pieces per chunk of ``polyline_distance``'s pruned search (capsule bounds per chunk pair first).
CHUNK_PIECES = 8
#: Piece pairs whose distances are computed at a time (bounds the memory of ``polyline_distance``).
PIECE_PAIR_BLOCK = 1 << 16


def _dot(u, v):
    return np.einsum("...i,...i->...", u, v)


def segment_distance(P0, P1, Q0, Q1):
    """Exact distance between the segments P0 P1 and Q0 Q1 and the parameters of their closest points.

    .. math:: d = \\min_{s, t \\in [0, 1]} \\lVert P_0 + s (P_1 - P_0) - Q_0 - t (Q_1 - Q_0) \\rVert

    The squared distance is a convex quadratic of (s, t) over the unit square: its minimum is the
    closest points of the two lines when they lie on both segments (computed from d1 x d2, accurate
    also near parallel), else on an edge of the square,
    where it is the clamped projection of an end point onto the other segment (Ericson 2005 section
    5.1.9). All five candidates are evaluated and the nearest kept, which covers crossing, parallel,
    collinear and zero-length segments (a point: every parameter is the same point) without a
    special case.

    Parameters
    ----------
    P0, P1 : array_like (..., 3) [m]
        End points of the first segments.
    Q0, Q1 : array_like (..., 3) [m]
        End points of the second segments (broadcast against the first).

    Returns
    -------
    d : ndarray (...) [m]
        Distance between the segments.
    s : ndarray (...) [-]
        Parameter in [0, 1] of the closest point on P0 P1.
    t : ndarray (...) [-]
        Parameter in [0, 1] of the closest point on Q0 Q1.

    References
    ----------
    Ericson, C. (2005). Real-Time Collision Detection, section 5.1.9 (ClosestPtSegmentSegment).
    """
    P0, P1, Q0, Q1 = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (P0, P1, Q0, Q1)))
    d1, d2, r = P1 - P0, Q1 - Q0, P0 - Q0
    a, e, f = _dot(d1, d1), _dot(d2, d2), _dot(d2, r)
    c, b = _dot(d1, r), _dot(d1, d2)
    a_ = np.where(a > POINT_EPS, a, 1.0)  # a zero-length segment: every s is the same point
    e_ = np.where(e > POINT_EPS, e, 1.0)
    # the lines' closest points from n = d1 x d2 (no cancellation of a e - b^2 near parallel):
    # s = ((Q0 - P0) x d2) . n / |n|^2, t = ((Q0 - P0) x d1) . n / |n|^2, whenever n != 0
    n = np.cross(d1, d2)
    nn = _dot(n, n)
    general = (a > POINT_EPS) & (e > POINT_EPS) & (nn > 0.0)
    nn_ = np.where(general, nn, 1.0)
    s_line = np.where(general, _dot(np.cross(-r, d2), n) / nn_, 0.0)
    t_line = np.where(general, _dot(np.cross(-r, d1), n) / nn_, 0.0)
    one, zero = np.ones_like(a), np.zeros_like(a)
    # candidates: the lines' closest points (clamped), and the best point of each edge of the unit
    # square (s = 0, s = 1, t = 0, t = 1): the convex quadratic's minimum over the square is one of
    # them, also for parallel and collinear segments (where the lines' solution does not exist)
    S = np.stack([s_line, zero, one, -c / a_, (b - c) / a_], axis=-1)
    T = np.stack([t_line, f / e_, (b + f) / e_, zero, one], axis=-1)
    S, T = np.clip(S, 0.0, 1.0), np.clip(T, 0.0, 1.0)
    gap = r[..., None, :] + S[..., None] * d1[..., None, :] - T[..., None] * d2[..., None, :]
    dist = np.sqrt(_dot(gap, gap))
    k = np.argmin(dist, axis=-1)[..., None]
    take = lambda x: np.take_along_axis(x, k, axis=-1)[..., 0]  # noqa: E731
    return take(dist), take(S), take(T)


def platform_faces(robot):
    """The platform body as half-spaces n_k . x + o_k <= 0 in the platform frame (``platform.body``).

    ``hull``: the faces of the convex hull of the attachments b_i (scipy.spatial.ConvexHull, Qhull;
    coplanar triangles merged), None when the attachments span no volume (a point mass, a flat or
    linear platform); a ``BoxBody``: its six faces; ``none``: None.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    faces : ndarray (F, 4) or None
        Rows (n_x, n_y, n_z, o) with unit outward normals n [-] and offsets o [m]; None: no body.
    """
    body = robot.platform.body
    if isinstance(body, BoxBody):
        c, h = np.asarray(body.centre, dtype=float), np.asarray(body.half, dtype=float)
        eye = np.eye(3)
        return np.concatenate([np.column_stack([eye, -c - h]), np.column_stack([-eye, c - h])], axis=0)
    if body == "none":
        return None
    b = robot.arrays.b
    if np.linalg.matrix_rank(b - b.mean(axis=0), tol=1e-9) < 3:
        return None
    from scipy.spatial import ConvexHull  # lazy: scipy.spatial is 0.2-0.4 s of every command's start-up

    eq = ConvexHull(b).equations
    eq = eq / np.linalg.norm(eq[:, :3], axis=1, keepdims=True)
    _, first = np.unique(np.round(eq, 12), axis=0, return_index=True)
    return eq[np.sort(first)]


def clip_segments(X0, X1, faces):
    """Exact chord of segments X0 X1 inside a convex body (Cyrus-Beck clipping) and its depth.

    With g_k(s) = n_k . X(s) + o_k (affine in s; inside: every g_k <= 0) the chord is
    [s_in, s_out] = {s in [0, 1]: g_k(s) <= 0 for every k}. Its depth is the largest distance of a
    chord point to the boundary, max_s min_k (-g_k(s)): the maximum of a concave piecewise-linear
    function, found among the chord's ends and the crossings of two faces' lines.

    Parameters
    ----------
    X0, X1 : ndarray (..., 3) [m]
        Segment end points in the frame of ``faces``.
    faces : ndarray (F, 4)
        Half-spaces n . x + o <= 0 with unit normals (``platform_faces``).

    Returns
    -------
    s_in, s_out : ndarray (...) [-]
        The chord inside the body (closed half-spaces); NaN where the segment misses it.
    depth : ndarray (...) [m]
        Largest depth of a chord point (0 where the segment misses the body or only touches it).

    References
    ----------
    Cyrus and Beck 1978; Ericson 2005, section 5.3.8.
    """
    n, o = faces[:, :3], faces[:, 3]
    g0 = np.einsum("...a,fa->...f", X0, n) + o
    slope = np.einsum("...a,fa->...f", X1 - X0, n)
    moving = slope != 0.0
    cut = -g0 / np.where(moving, slope, 1.0)
    lo = np.max(np.where(moving & (slope < 0), cut, 0.0), axis=-1, initial=0.0)
    hi = np.min(np.where(moving & (slope > 0), cut, 1.0), axis=-1, initial=1.0)
    outside = np.any(~moving & (g0 > 0), axis=-1)
    hit = (lo <= hi) & ~outside
    s_in, s_out = np.where(hit, lo, np.nan), np.where(hit, hi, np.nan)
    # depth: phi_k(s) = -g_k(s) = c_k + e_k s; candidates: the chord's ends and pairwise crossings
    # (F^2 candidates per segment: computed for the segments that meet the body, a block at a time)
    depth = np.zeros(lo.shape)
    where = np.flatnonzero(hit.ravel())
    F = faces.shape[0]
    cc_all, ee_all = -g0.reshape(-1, F), -slope.reshape(-1, F)
    lo_all, hi_all, flat = lo.ravel(), hi.ravel(), depth.reshape(-1)
    for start in range(0, len(where), DEPTH_BLOCK):
        w = where[start : start + DEPTH_BLOCK]
        cc, ee, a, z = cc_all[w], ee_all[w], lo_all[w], hi_all[w]
        de = ee[:, :, None] - ee[:, None, :]
        ok = de != 0.0
        cross = (cc[:, None, :] - cc[:, :, None]) / np.where(ok, de, 1.0)
        cross = np.where(ok, cross, a[:, None, None]).reshape(len(w), -1)
        cand = np.clip(np.concatenate([a[:, None], z[:, None], cross], axis=1), a[:, None], z[:, None])
        phi = np.min(cc[:, None, :] + ee[:, None, :] * cand[:, :, None], axis=-1)
        flat[w] = np.maximum(np.max(phi, axis=-1), 0.0)
    return s_in, s_out, depth


def body_sphere(robot, faces):
    """A ball that holds the platform body of ``platform_faces``: centred at the mean of the body's
    vertices (a ``BoxBody``'s eight corners, else the attachments b_i, whose convex hull the faces
    bound), its radius their largest distance from the centre.

    Parameters
    ----------
    robot : Robot
    faces : ndarray (F, 4) or None
        ``platform_faces(robot)``.

    Returns
    -------
    (ndarray (3,) [m], float [m]) or None
        None where there is no body.
    """
    if faces is None:
        return None
    body = robot.platform.body
    if isinstance(body, BoxBody):
        c, h = np.asarray(body.centre, dtype=float), np.asarray(body.half, dtype=float)
        signs = np.array(list(itertools.product((-1.0, 1.0), repeat=3)))
        v = c + signs * h
    else:
        v = np.asarray(robot.arrays.b, dtype=float)
    centre = v.mean(axis=0)
    return centre, float(np.sqrt(_dot(v - centre, v - centre)).max())


def far_pieces(X0, X1, centre, radius):
    """The segments X0 X1 that provably miss a ball (centre, radius): their midpoint is farther
    from the centre than the radius plus half their length, with a margin of 1e-9 (1 + radius) m
    far above round-off (so a segment ``clip_segments`` finds touching a body inside the ball is
    never among them).

    .. math:: |M - c| - |X_1 - X_0| / 2 > \\rho + 10^{-9} (1 + \\rho), \\qquad M = (X_0 + X_1) / 2

    Parameters
    ----------
    X0, X1 : ndarray (..., 3) [m]
        Segment end points.
    centre : ndarray (3,) [m]
    radius : float [m]

    Returns
    -------
    ndarray (...) of bool
    """
    mid, half = (X0 + X1) / 2.0 - centre, (X1 - X0) / 2.0
    return np.sqrt(_dot(mid, mid)) - np.sqrt(_dot(half, half)) > radius + 1e-9 * (1.0 + radius)


def shared_pairs(robot):
    """The cable pairs that share an end point by construction, not tested for interference: the
    same attachment b_i = b_j (``at`` "B"; every pair of a point mass) or two fixed pulleys at the
    same anchor A_i = A_j ("D"); within ``SAME_POINT_M``.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    list of (int, int, str)
        (i, j, at) with 0-based i < j, in ascending order.
    """
    a = robot.arrays
    out = []
    for i, j in itertools.combinations(range(robot.m), 2):
        if robot.point_mass or np.allclose(a.b[i], a.b[j], rtol=0.0, atol=SAME_POINT_M):
            out.append((i, j, "B"))
        elif a.kind[i] == 0 and a.kind[j] == 0 and np.allclose(a.A[i], a.A[j], rtol=0.0, atol=SAME_POINT_M):
            out.append((i, j, "D"))
    return out


def cable_segments(robot, p, R):
    """End points of every cable's free span at poses: B_i = p + R b_i (p itself on a point mass)
    and the sheave exit points D_i (``pulleys.pulley_state``; A_i for a fixed pulley).

    Parameters
    ----------
    robot : Robot
    p : ndarray (N, 3) [m]
        Reference points.
    R : ndarray (N, 3, 3) [-]
        Orientations (no part on a point mass).

    Returns
    -------
    B, D : ndarray (N, m, 3) [m]
    """
    B, st = pose_state(robot, p, R)  # a point mass is the platform with b_i = 0: B_i = p
    return B, st.D


def cable_polylines(robot, p, R, L0, pieces=POLYLINE_PIECES, cables=None):
    """Every heavy cable's free span at poses as a polyline: the points of Irvine's elastic catenary
    (``catenary.shape``) at s = L0_free k / K, k = 0..K, from B_i to the exit point D_i of the heavy
    pulley coupling (``cables.HeavyCables.exit_points``) under the rest lengths L0,

    .. math:: X_{ik} = B_i + x_i(s_k)\\, e_{h,i} + z_i(s_k)\\, u

    (e_h the horizontal unit vector from B_i toward D_i, u up). The first point is B_i and the last
    D_i exactly; a weightless cable (w_i = 0) is its straight chord cut in K equal pieces, and so is a
    cable whose catenary has no solution there (``catenary.SPAN_STATUSES`` infeasible).

    Parameters
    ----------
    robot : Robot
    p : ndarray (N, 3) [m]
        Reference points.
    R : ndarray (N, 3, 3) [-]
        Orientations.
    L0 : ndarray (N, m) [m]
        Rest lengths of the whole cables (as commanded at those poses).
    pieces : int
        K, the straight pieces per cable (>= 1).
    cables : mapping, optional
        The heavy cables already solved at these poses under L0 (``cables.heavy_cables``' D
        (N, m, 3) [m], H, V_B (N, m) [N] and L0_free (N, m) [m], e.g. from its compiled twin), used
        in place of solving the coupling again.

    Returns
    -------
    X : ndarray (N, m, K + 1, 3) [m]
        The polylines' points, from B_i (k = 0) to D_i (k = K).

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    cab = HeavyCables(robot)
    if cables is None:
        x = cab.exit_points(p, R, np.asarray(L0, dtype=float))
        sp, L0f = x["state"].span, x["state"].L0_free
        H, V_B, B, D, e_h = sp.H, sp.V_B, p[:, None, :] + x["r"], x["D"], x["e_h"]
    else:
        H, V_B, L0f, D = (np.asarray(cables[k], dtype=float) for k in ("H", "V_B", "L0_free", "D"))
        B = p[:, None, :] + np.einsum("nab,mb->nma", R, cab.b)
        e_h = cab.spans(D, B)[3]
    xs, zs = shape(H, V_B, L0f, cab.w, cab.EA, n=pieces + 1)
    X = B[:, :, None, :] + xs[..., None] * e_h[:, :, None, :] + zs[..., None] * cab.up
    X[:, :, 0, :], X[:, :, -1, :] = B, D
    frac = np.linspace(0.0, 1.0, pieces + 1)[:, None]
    chord = B[:, :, None, :] + frac * (D - B)[:, :, None, :]
    straight = (cab.w == 0.0)[None, :] | ~np.isfinite(X).all(axis=(-1, -2))
    return np.where(straight[..., None, None], chord, X)


def polyline_distance(X, Y):
    """Exact distance between two polylines and the parameters of their closest points: the
    smallest ``segment_distance`` over the pairs of their straight pieces. Polylines of a multiple
    of CHUNK_PIECES pieces are searched chunk pair by chunk pair, skipping the chunk pairs whose
    capsule bound (``chord_capsules``) is above a distance already found: the same answer, to the
    bit, as measuring every piece pair.

    .. math:: d = \\min_{k, l} d(X_k X_{k+1}, Y_l Y_{l+1})

    Parameters
    ----------
    X : array_like (..., Ka + 1, 3) [m]
        Points of the first polylines (Ka pieces).
    Y : array_like (..., Kb + 1, 3) [m]
        Points of the second polylines (broadcast against the first).

    Returns
    -------
    d : ndarray (...) [m]
        Distance between the polylines.
    s : ndarray (...) [-]
        Parameter of the closest point on X, (k + s_k) / Ka: piece k, at s_k in it.
    t : ndarray (...) [-]
        Parameter of the closest point on Y, (l + t_l) / Kb.

    References
    ----------
    Ericson, C. (2005). Real-Time Collision Detection, section 5.1.9 (per piece pair).
    """
    X, Y = np.asarray(X, dtype=float), np.asarray(Y, dtype=float)
    Ka, Kb = X.shape[-2] - 1, Y.shape[-2] - 1
    if Ka == 1 and Kb == 1:  # two segments: no search over pieces
        return segment_distance(X[..., 0, :], X[..., 1, :], Y[..., 0, :], Y[..., 1, :])
    lead = np.broadcast_shapes(X.shape[:-2], Y.shape[:-2])
    X = np.broadcast_to(X, lead + X.shape[-2:]).reshape(-1, Ka + 1, 3)
    Y = np.broadcast_to(Y, lead + Y.shape[-2:]).reshape(-1, Kb + 1, 3)
    if Ka % CHUNK_PIECES == 0 and Kb % CHUNK_PIECES == 0 and Ka * Kb > CHUNK_PIECES**2:
        d, s, t = _chunked_distance(X, Y)
        return d.reshape(lead), s.reshape(lead), t.reshape(lead)
    M = len(X)
    d, s, t = np.empty(M), np.empty(M), np.empty(M)
    step = max(1, PIECE_PAIR_BLOCK // (Ka * Kb))
    for a in range(0, M, step):
        x, y = X[a : a + step], Y[a : a + step]
        dd, ss, tt = segment_distance(
            x[:, :-1, None, :], x[:, 1:, None, :], y[:, None, :-1, :], y[:, None, 1:, :]
        )
        n = len(x)
        dd, ss, tt = dd.reshape(n, -1), ss.reshape(n, -1), tt.reshape(n, -1)
        k = np.argmin(dd, axis=1)
        rows = np.arange(n)
        ka, kb = np.divmod(k, Kb)
        d[a : a + n] = dd[rows, k]
        s[a : a + n] = (ka + ss[rows, k]) / Ka
        t[a : a + n] = (kb + tt[rows, k]) / Kb
    return d.reshape(lead), s.reshape(lead), t.reshape(lead)


def chord_capsules(X):
    """Each polyline's capsule about its chord: the chord X_0 X_K and the largest distance of a
    vertex from it. Every straight piece lies inside (a capsule is convex and holds both ends of
    each piece), so the distance between two polylines is at least that of their chords minus both
    radii.

    .. math:: \\rho = \\max_k d(X_k, X_0 X_K), \\qquad
              d(X, Y) \\ge d(X_0 X_K, Y_0 Y_K) - \\rho_X - \\rho_Y

    Parameters
    ----------
    X : array_like (..., K + 1, 3) [m]
        Points of the polylines.

    Returns
    -------
    rho : ndarray (...) [m]
        Capsule radius of each polyline about its chord.
    """
    X = np.asarray(X, dtype=float)
    A, d = X[..., :1, :], X[..., -1:, :] - X[..., :1, :]
    dd = _dot(d, d)
    u = np.clip(_dot(X - A, d) / np.where(dd > POINT_EPS, dd, 1.0), 0.0, 1.0)
    gap = X - A - u[..., None] * d
    return np.sqrt(_dot(gap, gap)).max(axis=-1)


def pairs_to_measure(X, pairs, radius, closest=True):
    """The pose-pair entries whose polyline distance ``_block`` must compute exactly: those whose
    lower bound (``chord_capsules``: chord distance minus both capsule radii) is below the pair's
    contact distance r_i + r_j (the pair may interfere) or not above the smallest upper bound of the
    pose (the pair may be the closest: an upper bound is the distance between two actual vertices,
    those nearest the chords' closest points). Every other pair neither interferes nor is the
    closest, exactly: ``interference`` leaves its distance NaN.

    Parameters
    ----------
    X : ndarray (N, m, K + 1, 3) [m]
        The cables' polylines at N poses.
    pairs : ndarray (P, 2)
        Cable pairs i < j (0-based).
    radius : ndarray (m,) [m]
        Cable radii.
    closest : bool
        Also the pairs that may be the closest (False: only those that may interfere).

    Returns
    -------
    need : ndarray (N, P) of bool
        With ``closest``, at least one entry per pose (the pair of the smallest upper bound).
    """
    K = X.shape[-2] - 1
    i, j = pairs[:, 0], pairs[:, 1]
    rho = chord_capsules(X)
    c, sc, tc = segment_distance(X[:, i, 0], X[:, i, -1], X[:, j, 0], X[:, j, -1])
    lower = c - rho[:, i] - rho[:, j]
    if not closest:
        return lower < radius[i] + radius[j]
    n = np.arange(len(X))[:, None]
    gap = X[n, i, np.rint(sc * K).astype(int)] - X[n, j, np.rint(tc * K).astype(int)]
    upper = np.sqrt(_dot(gap, gap))
    return (lower < radius[i] + radius[j]) | (lower <= upper.min(axis=1, keepdims=True))


def _chunked_distance(X, Y):
    """``polyline_distance`` of (M, Ka + 1, 3) and (M, Kb + 1, 3) polylines, Ka and Kb multiples of
    CHUNK_PIECES, exactly: the pieces are measured only in the chunk pairs whose capsule bound
    (``chord_capsules`` of the chunks) is not above the smallest distance between two of their
    vertices; the nearest piece pair (the first in (k, l) order among equals) is that of the
    exhaustive search."""
    c = CHUNK_PIECES
    Ka, Kb = X.shape[1] - 1, Y.shape[1] - 1
    ia = np.arange(Ka // c)[:, None] * c + np.arange(c + 1)
    ib = np.arange(Kb // c)[:, None] * c + np.arange(c + 1)
    Xc, Yc = X[:, ia], Y[:, ib]  # (M, Ca, c + 1, 3), (M, Cb, c + 1, 3)
    ra, rb = chord_capsules(Xc), chord_capsules(Yc)
    cd, cs, ct = segment_distance(
        Xc[:, :, None, 0], Xc[:, :, None, -1], Yc[:, None, :, 0], Yc[:, None, :, -1]
    )  # (M, Ca, Cb)
    lower = cd - ra[:, :, None] - rb[:, None, :]
    M, Ca, Cb = lower.shape
    n = np.arange(M)[:, None, None]
    va = np.arange(Ca)[None, :, None] * c + np.rint(cs * c).astype(int)
    vb = np.arange(Cb)[None, None, :] * c + np.rint(ct * c).astype(int)
    gap = X[n, va] - Y[n, vb]
    upper = np.sqrt(_dot(gap, gap)).reshape(M, -1).min(axis=1)
    m, ka, kb = (lower <= upper[:, None, None]).nonzero()  # at least one chunk pair per polyline pair
    x, y = Xc[m, ka], Yc[m, kb]
    dd, ss, tt = segment_distance(
        x[:, :-1, None, :], x[:, 1:, None, :], y[:, None, :-1, :], y[:, None, 1:, :]
    )
    pa = ka[:, None, None] * c + np.arange(c)[None, :, None]  # the pieces' indices in X and Y
    pb = kb[:, None, None] * c + np.arange(c)[None, None, :]
    g = np.broadcast_to(pa * Kb + pb, dd.shape).ravel()
    rows = np.broadcast_to(m[:, None, None], dd.shape).ravel()
    order = np.lexsort((g, dd.ravel(), rows))
    first = order[np.r_[True, rows[order][1:] != rows[order][:-1]]]
    d, s, t = np.empty(M), np.empty(M), np.empty(M)
    at = rows[first]
    d[at] = dd.ravel()[first]
    s[at] = (g[first] // Kb + ss.ravel()[first]) / Ka
    t[at] = (g[first] % Kb + tt.ravel()[first]) / Kb
    return d, s, t


def clip_polylines(X, faces, sphere=None):
    """The chords of polylines inside a convex body: every straight piece clipped exactly
    (``clip_segments``) and the pieces' chords joined. With the body's bounding ``sphere``, the
    pieces that provably miss it (``far_pieces``) are not clipped: they miss the body, as
    ``clip_segments`` would find; the others are clipped as without it (the same result, to the bit).

    Parameters
    ----------
    X : ndarray (..., K + 1, 3) [m]
        Points of the polylines in the frame of ``faces`` (K pieces; K = 1: a segment).
    faces : ndarray (F, 4)
        Half-spaces n . x + o <= 0 with unit normals (``platform_faces``).
    sphere : tuple (ndarray (3,) [m], float [m]), optional
        A ball (centre, radius) that holds the body (``body_sphere``).

    Returns
    -------
    s_in, s_out : ndarray (...) [-]
        First entry and last exit of the polyline, (k + s) / K on piece k; NaN where it misses
        the body (a convex body and a curved cable may meet in more than one chord: they lie between).
    length : ndarray (...) [m]
        Length of the polyline inside the body (the sum of the pieces' chords; 0 where none).
    depth : ndarray (...) [m]
        Largest depth of a point of the polyline inside the body (0 where none or touching).
    """
    K = X.shape[-2] - 1
    X0, X1 = X[..., :-1, :], X[..., 1:, :]
    if sphere is None:
        si, so, dep = clip_segments(X0, X1, faces)
    else:  # clip only the pieces that may meet the body; the others miss it (NaN, depth 0)
        near = ~far_pieces(X0, X1, *sphere)
        si, so, dep = np.full(near.shape, np.nan), np.full(near.shape, np.nan), np.zeros(near.shape)
        si[near], so[near], dep[near] = clip_segments(X0[near], X1[near], faces)
    hit = ~np.isnan(si)
    piece = np.linalg.norm(X[..., 1:, :] - X[..., :-1, :], axis=-1)
    length = np.where(hit, (so - si) * piece, 0.0).sum(axis=-1)
    if K == 1:
        return si[..., 0], so[..., 0], length, dep[..., 0]
    k = np.arange(K)
    met = hit.any(axis=-1)
    lo = np.min(np.where(hit, (k + si) / K, np.inf), axis=-1)
    hi = np.max(np.where(hit, (k + so) / K, -np.inf), axis=-1)
    return np.where(met, lo, np.nan), np.where(met, hi, np.nan), length, dep.max(axis=-1)


class Interference(NamedTuple):
    """Interference of the cables at N poses (``interference``); cables and pairs 0-based here.

    pairs (K, 2) the tested pairs i < j; distance (N, K) [m]; s (N, K, 2) [-] parameters of the
    closest points (heavy cables: NaN for a pair that provably neither interferes nor is the
    closest, ``pairs_to_measure``); cc (N, K) the interfering pairs (distance < r_i + r_j); shared: list of
    (i, j, at) (``shared_pairs``); cp (N, m) cables through the body; s_in, s_out (N, m) [-] and
    length, depth (N, m) [m] of the chord inside (NaN, 0 where none); free (N,) no interference;
    dmin (N,) [m] the smallest tested distance and dmin_pair (N,) its index in pairs (-1: no pair
    tested); has_body: a platform body was tested; pieces: the straight pieces per cable (1: the
    straight spans of massless cables, ``POLYLINE_PIECES``: the catenaries' polylines).
    """

    pairs: np.ndarray
    distance: np.ndarray
    s: np.ndarray
    cc: np.ndarray
    shared: list
    cp: np.ndarray
    s_in: np.ndarray
    s_out: np.ndarray
    length: np.ndarray
    depth: np.ndarray
    free: np.ndarray
    dmin: np.ndarray
    dmin_pair: np.ndarray
    has_body: bool
    pieces: int = 1


def interference(robot, p, rotvec=None, R=None, L0=None, pieces=POLYLINE_PIECES, cables=None, closest=True):
    """Cable-cable and cable-platform interference at poses (p, R) (the module's conventions).

    Parameters
    ----------
    robot : Robot
    p : array_like (N, 3) [m] or (N, 6) [m, rad]
        Reference points of the platform, or poses (x, y, z, rx, ry, rz).
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Orientations (default identity).
    R : array_like (N, 3, 3) [-], optional
        Orientation matrices, in place of ``rotvec``.
    L0 : array_like (N, m) or (m,) [m], optional
        Rest lengths of the whole cables at the poses: needed by heavy cables (``Robot.heavy``),
        whose spans are then the catenaries' polylines (``cable_polylines``), wherever something is
        tested (a pair or a platform body); ignored for massless cables.
    pieces : int
        Straight pieces of a heavy cable's polyline.
    cables : mapping, optional
        Heavy cables: their state at the poses under ``L0`` (``cable_polylines``' ``cables``: D,
        H, V_B, L0_free, each (N, m, ...)), in place of solving the pulley coupling again.
    closest : bool
        Find each pose's closest pair (``dmin``, ``dmin_pair``). False (heavy cables): only the pairs
        that may interfere are measured (``pairs_to_measure``), so ``free``, ``cc`` and ``cp`` are
        exact and ``dmin`` is NaN, ``dmin_pair`` -1 (what a test of interference alone needs).

    Returns
    -------
    Interference

    Raises
    ------
    CdprError
        A pose that is not finite; heavy cables without their rest lengths.
    """
    if R is None:
        p, R = pose_arrays(p, rotvec)
    else:
        p, R = np.atleast_2d(np.asarray(p, dtype=float)), np.asarray(R, dtype=float).reshape(-1, 3, 3)
    if not (np.isfinite(p).all() and np.isfinite(R).all()):
        raise CdprError("interference: every pose must be finite")
    m = robot.m
    shared = shared_pairs(robot)
    skip = {(i, j) for i, j, _ in shared}
    pairs = np.array(
        [(i, j) for i, j in itertools.combinations(range(m), 2) if (i, j) not in skip], dtype=int
    ).reshape(-1, 2)
    radius = np.array([c.material.diameter for c in robot.cables]) / 2.0
    faces = platform_faces(robot)
    heavy = robot.heavy and (len(pairs) > 0 or faces is not None)
    if heavy:
        if L0 is None:
            raise CdprError(
                f"{robot.source}: heavy cables (cable.linear_density_kg_m > 0) sag under their tensions: "
                "their interference at a pose needs the cables' rest lengths (cdpr point and cdpr compensate "
                "test their solved poses)"
            )
        L0 = np.broadcast_to(np.asarray(L0, dtype=float), (len(p), m))
        if int(pieces) < 1:
            raise CdprError(f"interference: a polyline needs at least one piece, got {pieces}")
    K = int(pieces) if heavy else 1
    sphere = body_sphere(robot, faces) if K > 1 else None  # pieces far from the body: not clipped
    block = max(1, POSE_BLOCK // K)
    blocks = [
        _block(
            robot,
            p[k : k + block],
            R[k : k + block],
            None if not heavy else L0[k : k + block],
            K,
            pairs,
            radius,
            faces,
            sphere,
            None if not heavy or cables is None else {c: cables[c][k : k + block] for c in CABLE_STATE},
            closest,
        )
        for k in range(0, max(len(p), 1), block)
    ]
    cat = [np.concatenate([b[f] for b in blocks], axis=0) for f in range(len(blocks[0]))]
    dist, s, cc, cp, s_in, s_out, length, depth, dmin, dmin_pair = cat
    free = ~cc.any(axis=1) & ~cp.any(axis=1)
    return Interference(
        pairs,
        dist,
        s,
        cc,
        shared,
        cp,
        s_in,
        s_out,
        length,
        depth,
        free,
        dmin,
        dmin_pair,
        faces is not None,
        K,
    )


def _block(robot, p, R, L0, K, pairs, radius, faces, sphere, cables=None, closest=True):
    """``interference`` of one block of poses: the arrays of ``Interference`` but pairs, shared,
    free, has_body and pieces. L0 None: straight spans (one piece each), else the catenaries'
    polylines of K pieces (from ``cables`` where given); ``sphere`` the body's bounding ball
    (``clip_polylines``), None to clip every piece."""
    N, m = len(p), robot.m
    if L0 is None:
        B, D = cable_segments(robot, p, R)
        X = np.stack([B, D], axis=2)
    else:
        X = cable_polylines(robot, p, R, L0, K, cables)
    if len(pairs):
        i, j = pairs[:, 0], pairs[:, 1]
        if K == 1:
            dist, si, sj = polyline_distance(X[:, i], X[:, j])
        else:  # exact where a pair may interfere or be the closest; NaN where its bound proves neither
            dist, si, sj = np.full((3, N, len(pairs)), np.nan)
            need = pairs_to_measure(X, pairs, radius, closest)
            n, q = need.nonzero()
            if len(n):  # (none without ``closest`` where no pair can interfere)
                dist[need], si[need], sj[need] = polyline_distance(X[n, i[q]], X[n, j[q]])
        s = np.stack([si, sj], axis=-1)
        cc = dist < radius[i] + radius[j]
        k = np.argmin(np.where(np.isnan(dist), np.inf, dist), axis=1)
        dmin, dmin_pair = dist[np.arange(N), k], k
        if not closest and K > 1:
            dmin, dmin_pair = np.full(N, np.nan), np.full(N, -1)
    else:
        dist, s, cc = np.zeros((N, 0)), np.zeros((N, 0, 2)), np.zeros((N, 0), dtype=bool)
        dmin, dmin_pair = np.full(N, np.nan), np.full(N, -1)
    if faces is None:
        s_in, s_out, length, depth = (
            np.full((N, m), np.nan),
            np.full((N, m), np.nan),
            np.zeros((N, m)),
            np.zeros((N, m)),
        )
    else:
        # the polylines in the platform frame: x = R^T (X - p)
        x = np.einsum("nba,nmkb->nmka", R, X - p[:, None, None, :])
        s_in, s_out, length, depth = clip_polylines(x, faces, sphere)
    cp = depth > DEPTH_TOL
    return dist, s, cc, cp, s_in, s_out, length, depth, dmin, dmin_pair


def report(res, n=0):
    """The JSON object of pose ``n`` of an ``Interference`` (cables from 1): interference_free,
    cable_cable (interfering pairs: cables, distance_m, s), shared (cables, at), cable_platform
    (cable, length_m, depth_m, s_in, s_out), dmin_m and dmin_pair (the closest tested pair).

    Parameters
    ----------
    res : Interference
    n : int
        Index of the pose.

    Returns
    -------
    dict
    """
    k = int(res.dmin_pair[n])
    return {
        "interference_free": bool(res.free[n]),
        "cable_cable": [
            {
                "cables": [int(i) + 1, int(j) + 1],
                "distance_m": float(res.distance[n, q]),
                "s": [float(res.s[n, q, 0]), float(res.s[n, q, 1])],
            }
            for q, (i, j) in enumerate(res.pairs)
            if res.cc[n, q]
        ],
        "shared": [{"cables": [i + 1, j + 1], "at": at} for i, j, at in res.shared],
        "cable_platform": [
            {
                "cable": int(c) + 1,
                "length_m": float(res.length[n, c]),
                "depth_m": float(res.depth[n, c]),
                "s_in": float(res.s_in[n, c]),
                "s_out": float(res.s_out[n, c]),
            }
            for c in np.flatnonzero(res.cp[n])
        ],
        "dmin_m": None if k < 0 else float(res.dmin[n]),
        "dmin_pair": None if k < 0 else [int(res.pairs[k, 0]) + 1, int(res.pairs[k, 1]) + 1],
    }


#: The table columns of interference (``columns``), in order.
COLUMNS = ("interference_free", "n_cc", "n_cp", "dmin_m", "cc_pairs", "cp_cables")


def columns(res):
    """The table columns of an ``Interference`` (``COLUMNS``): interference_free, n_cc, n_cp,
    dmin_m, cc_pairs ("i-j;k-l", i < j ascending, cables from 1) and cp_cables ("i;j" ascending),
    the strings empty when none.

    Parameters
    ----------
    res : Interference

    Returns
    -------
    dict
        Column name -> ndarray (N,): bool, int, int, float [m] (NaN: no pair tested), str, str.
    """
    labels = [f"{i + 1}-{j + 1}" for i, j in res.pairs]
    cc_pairs = np.array([";".join(lab for lab, x in zip(labels, row) if x) for row in res.cc], dtype=object)
    cp_cables = np.array([";".join(str(c + 1) for c in np.flatnonzero(row)) for row in res.cp], dtype=object)
    return {
        "interference_free": res.free.copy(),
        "n_cc": res.cc.sum(axis=1).astype(np.int64),
        "n_cp": res.cp.sum(axis=1).astype(np.int64),
        "dmin_m": res.dmin.astype(float),
        "cc_pairs": cc_pairs,
        "cp_cables": cp_cables,
    }


def interference_free(robot, p, rotvec=None, L0=None):
    """Whether one pose is free of interference (``interference``); None when the pose (or, with
    heavy cables, a rest length) is not finite (an unsolved point).

    Parameters
    ----------
    robot : Robot
    p : array_like (3,) [m]
        Reference point.
    rotvec : array_like (3,) [rad], optional
        Orientation (default identity).
    L0 : array_like (m,) [m], optional
        Rest lengths of the whole cables: heavy cables' catenaries (``interference``).

    Returns
    -------
    bool or None
    """
    p = np.asarray(p, dtype=float).reshape(1, 3)
    rv = np.zeros((1, 3)) if rotvec is None else np.asarray(rotvec, dtype=float).reshape(1, 3)
    if not (np.isfinite(p).all() and np.isfinite(rv).all()):
        return None
    if L0 is not None:
        L0 = np.asarray(L0, dtype=float).reshape(1, -1)
        if robot.heavy and not np.isfinite(L0).all():
            return None
    return bool(interference(robot, p, rv, L0=L0).free[0])
