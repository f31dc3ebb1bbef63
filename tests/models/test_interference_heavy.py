"""Interference of heavy cables (issues 38, 39): the span is the catenary's polyline. A cable whose
chord misses a box body but whose sagging curve runs through it is flagged, and the other way round;
the polyline's chord inside the body and its depth agree with the catenary sampled densely; a
weight w -> 0 gives the straight spans' answer; the rest lengths are required."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
import yaml

from cdpr.errors import CdprError
from cdpr.models.cables import HeavyCables
from cdpr.models.catenary import shape
from cdpr.models.interference import (
    DEPTH_TOL,
    POLYLINE_PIECES,
    body_sphere,
    cable_polylines,
    clip_polylines,
    clip_segments,
    far_pieces,
    interference,
    interference_free,
    platform_faces,
    polyline_distance,
    segment_distance,
)
from cdpr.models.platform import pose_arrays
from cdpr.robot import robot_from_dict

ROOT = Path(__file__).resolve().parents[2]
WALL = ROOT / "tests" / "data" / "wall_crossed.yaml"
P = np.array([[0.0, 0.0, 1.0]])
T_B = 500.0  # tension at every attachment [N]


def _shelf_robot(centre, half, density=1.0):
    """Cable 1 runs horizontally from the attachment b_1 = 0 to a fixed anchor 10 m away along +x,
    over (or through) a box body ``centre``/``half`` in front of it; cables 2-4 leave the other way."""
    B = [[0.0, 0.0, 0.0], [0.0, 0.3, 0.0], [0.0, -0.3, 0.0], [-0.1, 0.0, 0.05]]
    A = [[10.0, 0.0, 1.0], [-10.0, 0.3, 1.0], [-10.0, -0.3, 1.0], [-10.0, 0.0, 6.0]]
    data = {
        "platform": {"mass_kg": 10.0, "body": {"box": {"centre_m": centre, "half_m": half}}},
        "cable": {
            "young_modulus_Pa": 1e11,
            "diameter_m": 0.004,
            "max_tension_N": 5000.0,
            "linear_density_kg_m": density,
        },
        "pulley": {"kind": "fixed", "h_m": 0.0, "r_p_m": 0.0},
        "cables": [{"A_m": a, "B_m": b} for a, b in zip(A, B)],
    }
    return robot_from_dict(data, "shelf")


def _lengths(robot, p, rotvec=None, t=T_B):
    """Rest lengths under which every cable pulls with ``t`` at its attachment (the heavy inverse)."""
    p, R = pose_arrays(p, rotvec)
    return HeavyCables(robot).inverse(p, R, np.full((len(p), robot.m), t))["L0"]


def test_a_sagging_cable_through_a_shelf_below_its_chord_is_flagged():
    """The shelf's top is 1 cm below the chord: the straight cable misses it, the catenary (sag
    w l^2 / 8H = 0.25 m) dips into it from x = 0.1 m on."""
    robot = _shelf_robot([0.5, 0.0, -0.05], [0.4, 0.2, 0.04])
    massless = _shelf_robot([0.5, 0.0, -0.05], [0.4, 0.2, 0.04], density=0.0)
    L0 = _lengths(robot, P)
    heavy = interference(robot, P, L0=L0)
    straight = interference(massless, P)
    assert not straight.cp[0, 0] and straight.free[0]
    assert heavy.cp[0].tolist() == [True, False, False, False] and not heavy.free[0]
    assert heavy.pieces == POLYLINE_PIECES and straight.pieces == 1
    assert interference_free(robot, P[0], None, L0[0]) is False


def test_a_sagging_cable_under_a_body_its_chord_crosses_is_free():
    """The body reaches 5 mm below the chord: the straight cable runs through it, the catenary
    passes under it (about 10 mm down at x = 0.1 m already)."""
    robot = _shelf_robot([0.5, 0.0, 0.0225], [0.4, 0.2, 0.0275])
    massless = _shelf_robot([0.5, 0.0, 0.0225], [0.4, 0.2, 0.0275], density=0.0)
    heavy = interference(robot, P, L0=_lengths(robot, P))
    straight = interference(massless, P)
    assert straight.cp[0, 0] and straight.depth[0, 0] == pytest.approx(0.005, rel=1e-9)
    assert not heavy.cp.any() and heavy.free[0]


def test_the_polyline_chord_and_depth_agree_with_the_dense_catenary():
    """Cable 1 of the shelf robot: the chord inside the box (its length, its first entry and last
    exit, its depth) against 200001 points of the catenary (``catenary.shape``), within the
    polyline's distance to the curve (sag / K^2 = 0.06 mm)."""
    robot = _shelf_robot([0.5, 0.0, -0.05], [0.4, 0.2, 0.04])
    L0 = _lengths(robot, P)
    res = interference(robot, P, L0=L0)
    x = HeavyCables(robot).exit_points(*pose_arrays(P, None), L0)
    sp = x["state"].span
    xs, zs = shape(
        sp.H[0, 0], sp.V_B[0, 0], x["state"].L0_free[0, 0], robot.arrays.w[0], robot.arrays.ES[0], n=200001
    )
    pts = np.column_stack([xs, np.zeros_like(xs), zs])  # the cable's plane is x-z, B at the origin
    faces = platform_faces(robot)
    inside_depth = np.min(-(pts @ faces[:, :3].T + faces[:, 3]), axis=1)
    inside = inside_depth > 0
    s = np.linspace(0.0, 1.0, len(xs))
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    tol = 1e-4
    assert res.depth[0, 0] == pytest.approx(inside_depth.max(), abs=tol)
    assert res.s_in[0, 0] == pytest.approx(s[inside][0], abs=2e-3)
    assert res.s_out[0, 0] == pytest.approx(s[inside][-1], abs=2e-3)
    assert res.length[0, 0] == pytest.approx(seg[inside[1:] & inside[:-1]].sum(), abs=2e-3)
    assert res.depth[0, 0] > 0.02  # well inside: not a touch


def test_polyline_ends_are_the_attachment_and_the_exit_point():
    robot = _shelf_robot([0.5, 0.0, -0.05], [0.4, 0.2, 0.04])
    L0 = _lengths(robot, P)
    X = cable_polylines(robot, *pose_arrays(P, None), L0)
    assert X.shape == (1, 4, POLYLINE_PIECES + 1, 3)
    np.testing.assert_array_equal(X[0, :, 0], P[0] + robot.arrays.b)
    np.testing.assert_array_equal(X[0, :, -1], robot.arrays.A)  # fixed pulleys: D = A
    assert X[0, 0, POLYLINE_PIECES // 2, 2] < P[0, 2] + 1.0 / 2 - 0.2  # sags below the chord's middle


def _at(Z, v):
    """The point at parameter v of the polyline Z: (k + s_k) / K is piece k at s_k."""
    K = len(Z) - 1
    k = min(int(v * K), K - 1)
    return Z[k] + (v * K - k) * (Z[k + 1] - Z[k])


def test_polyline_distance_against_dense_sampling():
    """Two random polylines: the smallest piece-pair distance is the dense sampling's minimum."""
    rng = np.random.default_rng(3)
    for _ in range(20):
        X = np.cumsum(rng.normal(size=(7, 3)), axis=0)
        Y = np.cumsum(rng.normal(size=(5, 3)), axis=0) + rng.normal(size=3)
        d, s, t = polyline_distance(X, Y)
        u = np.linspace(0.0, 1.0, 301)[:, None]
        dense = lambda Z: np.concatenate([Z[k] + u * (Z[k + 1] - Z[k]) for k in range(len(Z) - 1)])  # noqa: E731
        A, B = dense(X), dense(Y)
        sampled = np.sqrt(((A[:, None] - B[None]) ** 2).sum(-1)).min()
        assert sampled - 1e-2 <= d <= sampled + 1e-12
        # the parameters point at the closest points: (k + s_k) / K
        assert np.linalg.norm(_at(X, s) - _at(Y, t)) == pytest.approx(d, abs=1e-12)


def test_one_piece_polylines_are_segments():
    rng = np.random.default_rng(4)
    a = [rng.normal(size=(50, 3)) for _ in range(4)]
    got = polyline_distance(np.stack(a[:2], axis=1), np.stack(a[2:], axis=1))
    for x, y in zip(got, segment_distance(*a)):
        np.testing.assert_array_equal(x, y)


def _heavy_wall(density):
    data = yaml.safe_load(WALL.read_text())
    data = copy.deepcopy(data)
    data["cable"]["linear_density_kg_m"] = density
    return robot_from_dict(data, "wall")


@pytest.mark.parametrize(
    ("pulley", "p", "rv"),
    [("fixed", [0.0, 0.0, 1.5], [0.0, 0.0, 0.0]), ("SR", [0.3, 0.3, 0.7], [0.12, 0.12, 0.0])],
)
def test_weight_to_zero_gives_the_straight_answer(pulley, p, rv):
    """The wall robot (crossing pairs at home with fixed pulleys, cable 6 through the platform at the
    issue's tilted pose) with w = 1e-9 kg/m: the catenaries' polylines give the straight spans'
    flags, pairs and chords (distances and parameters of the measured pairs within 1e-9)."""
    from cdpr.robot import with_pulleys

    heavy = _heavy_wall(1e-9)
    straight = _heavy_wall(0.0)
    if pulley == "fixed":
        heavy, straight = with_pulleys(heavy, "fixed"), with_pulleys(straight, "fixed")
    assert heavy.heavy and not straight.heavy
    pp, rr = np.array([p]), np.array([rv])
    a = interference(heavy, pp, rr, L0=_lengths(heavy, pp, rr, t=300.0))
    b = interference(straight, pp, rr)
    assert a.pieces == POLYLINE_PIECES and b.pieces == 1
    for name in ("cc", "cp", "free", "dmin_pair"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    for name in ("dmin", "s_in", "s_out", "length", "depth"):
        np.testing.assert_allclose(getattr(a, name), getattr(b, name), atol=1e-9, rtol=0, err_msg=name)
    kept = ~np.isnan(a.distance)  # heavy cables: the pairs a bound proves far are not measured
    assert kept[a.cc].all() and kept[0, a.dmin_pair[0]]
    np.testing.assert_allclose(a.distance[kept], b.distance[kept], atol=1e-9, rtol=0)
    np.testing.assert_allclose(a.s[kept], b.s[kept], atol=1e-9, rtol=0)
    if pulley == "fixed":
        assert a.cc.sum() == 6
    else:
        assert a.cp[0].tolist() == [False] * 5 + [True] + [False] * 2


def test_heavy_cables_need_their_rest_lengths():
    robot = _shelf_robot([0.5, 0.0, -0.05], [0.4, 0.2, 0.04])
    with pytest.raises(CdprError, match="rest lengths"):
        interference(robot, P)
    L0 = _lengths(robot, P)
    L0[0, 1] = np.nan
    assert interference_free(robot, P[0], None, L0[0]) is None


def _every_piece_pair(X, Y):
    """The exhaustive polyline distance: ``segment_distance`` of every piece pair, the first
    nearest in (k, l) order."""
    Ka, Kb = X.shape[-2] - 1, Y.shape[-2] - 1
    dd, ss, tt = segment_distance(
        X[..., :-1, None, :], X[..., 1:, None, :], Y[..., None, :-1, :], Y[..., None, 1:, :]
    )
    dd, ss, tt = (a.reshape(a.shape[:-2] + (-1,)) for a in (dd, ss, tt))
    k = np.argmin(dd, axis=-1)[..., None]
    pick = lambda a: np.take_along_axis(a, k, axis=-1)[..., 0]  # noqa: E731
    return pick(dd), (k[..., 0] // Kb + pick(ss)) / Ka, (k[..., 0] % Kb + pick(tt)) / Kb


def test_pruned_pairs_give_the_exhaustive_answer():
    """Heavy cables: ``interference`` measures only the pairs whose capsule bound allows them to
    interfere or to be the closest (``pairs_to_measure``). On CoGiRo at 0.5 kg/m (sags of tens of
    cm, cables crossing the platform's neighbourhood) over random tilted poses, and on the wall
    robot whose crossed cables touch, its flags, closest pair and measured distances equal those of
    every pair measured exhaustively; ``polyline_distance``'s chunked search gives the exhaustive
    search's distance and parameters to the bit; a pruned pair is truly farther than its contact
    distance and than the pose's closest pair."""
    rng = np.random.default_rng(7)
    cases = []
    for path, density, box in (
        (ROOT / "config" / "robots" / "cogiro.yaml", 0.5, ([-4, 4], [-3, 3], [0.8, 3.5])),
        (WALL, 0.2, ([-0.5, 0.5], [-0.5, 0.5], [0.6, 1.6])),
    ):
        data = yaml.safe_load(path.read_text())
        data["cable"]["linear_density_kg_m"] = density
        robot = robot_from_dict(data, path.stem)
        p = np.column_stack([rng.uniform(*lim, 60) for lim in box])
        rv = rng.uniform(-0.25, 0.25, (60, 3))
        cases.append((robot, p, rv, _lengths(robot, p, rv, t=800.0)))
    seen_pruned = 0
    for robot, p, rv, L0 in cases:
        res = interference(robot, p, rv, L0=L0)
        X = cable_polylines(robot, *pose_arrays(p, rv), L0)
        i, j = res.pairs[:, 0], res.pairs[:, 1]
        full, fs, ft = _every_piece_pair(X[:, i], X[:, j])
        got = polyline_distance(X[:, i], X[:, j])  # the chunked search: the exhaustive one's answer
        for a, b in zip(got, (full, fs, ft)):
            np.testing.assert_array_equal(a, b)
        radius = np.array([c.material.diameter for c in robot.cables]) / 2.0
        cc = full < radius[i] + radius[j]
        kept = ~np.isnan(res.distance)
        seen_pruned += int((~kept).sum())
        np.testing.assert_array_equal(res.distance[kept], full[kept])
        np.testing.assert_array_equal(res.s[..., 0][kept], fs[kept])
        np.testing.assert_array_equal(res.s[..., 1][kept], ft[kept])
        np.testing.assert_array_equal(res.cc, cc)
        np.testing.assert_array_equal(res.free, ~cc.any(axis=1) & ~res.cp.any(axis=1))
        np.testing.assert_array_equal(res.dmin, full.min(axis=1))
        assert (full[~kept] >= (radius[i] + radius[j])[None, :].repeat(len(p), 0)[~kept]).all()
        assert (full[~kept] >= full.min(axis=1, keepdims=True).repeat(len(i), 1)[~kept]).all()
    assert seen_pruned > 0  # the bound prunes (else this test tests nothing)


def test_pieces_far_from_the_body_are_not_clipped_and_change_nothing():
    """``clip_polylines`` with the body's bounding sphere clips only the pieces that may meet it:
    on CoGiRo at 0.5 kg/m over random, strongly tilted poses (cables through the platform among
    them) the chords, lengths and depths equal the clipping of every piece to the bit; most pieces
    are skipped, and every skipped piece truly misses the ball."""
    data = yaml.safe_load((ROOT / "config" / "robots" / "cogiro.yaml").read_text())
    data["cable"]["linear_density_kg_m"] = 0.5
    robot = robot_from_dict(data, "cogiro")
    rng = np.random.default_rng(11)
    p = np.column_stack([rng.uniform(-4, 4, 80), rng.uniform(-3, 3, 80), rng.uniform(0.8, 3.5, 80)])
    rv = rng.uniform(-0.9, 0.9, (80, 3))
    P, R = pose_arrays(p, rv)
    X = cable_polylines(robot, P, R, _lengths(robot, p, rv, t=800.0))
    faces = platform_faces(robot)
    x = np.einsum("nba,nmkb->nmka", R, X - P[:, None, None, :])
    ball = body_sphere(robot, faces)
    pruned, full = clip_polylines(x, faces, ball), clip_polylines(x, faces)
    for a, b in zip(pruned, full):
        np.testing.assert_array_equal(a, b)
    assert (full[3] > DEPTH_TOL).any()  # some cables pass through the body
    far = far_pieces(x[..., :-1, :], x[..., 1:, :], *ball)
    assert far.mean() > 0.5
    s_in = clip_segments(x[..., :-1, :], x[..., 1:, :], faces)[0]
    assert np.isnan(s_in[far]).all()
