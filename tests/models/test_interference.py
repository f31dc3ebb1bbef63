"""Interference (issue 39): the exact segment-segment distance against dense sampling, invariance
under rigid motions, a segment through a cube, crossing segments at a known distance, touching the
own attachment vertex, the wall robot's crossing pairs at its home pose and the robot file's
``platform.body``."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
import yaml

from cdpr.errors import CdprError
from cdpr.models.interference import (
    DEPTH_TOL,
    clip_segments,
    columns,
    interference,
    interference_free,
    platform_faces,
    report,
    segment_distance,
    shared_pairs,
)
from cdpr.models.platform import rotation_matrix
from cdpr.robot import BoxBody, load_robot, robot_from_dict, with_pulleys

ROOT = Path(__file__).resolve().parents[2]
WALL = ROOT / "tests" / "data" / "wall_crossed.yaml"
COGIRO = ROOT / "config" / "robots" / "cogiro_massless.yaml"
CDPR4 = ROOT / "config" / "robots" / "cdpr4.yaml"
N_SAMPLE = 401


def _sampled_min(P0, P1, Q0, Q1):
    """Smallest distance between N_SAMPLE x N_SAMPLE sample points of the two segments."""
    u = np.linspace(0.0, 1.0, N_SAMPLE)
    X = P0 + u[:, None] * (P1 - P0)
    Y = Q0 + u[:, None] * (Q1 - Q0)
    return float(np.sqrt(((X[:, None, :] - Y[None, :, :]) ** 2).sum(-1)).min())


def _special_segments(rng):
    """Parallel, collinear (overlapping and apart), anti-parallel, zero-length, nearly parallel
    and touching segments."""
    out = []
    for _ in range(8):
        P0, d = rng.normal(size=3), rng.normal(size=3)
        off = rng.normal(size=3)
        off -= off @ d / (d @ d) * d  # perpendicular offset
        for a, b in ((0.3, 1.4), (-2.0, -1.2), (1.5, 3.0), (0.2, 0.5)):
            out.append((P0, P0 + d, P0 + off + a * d, P0 + off + b * d))  # parallel
            out.append((P0, P0 + d, P0 + a * d, P0 + b * d))  # collinear
            out.append((P0, P0 + d, P0 + off + b * d, P0 + off + a * d))  # anti-parallel
        out.append((P0, P0, P0 + off, P0 + off + d))  # a point and a segment
        out.append((P0, P0 + d, P0 + off, P0 + off))  # a segment and a point
        out.append((P0, P0, P0 + off, P0 + off))  # two points
        out.append((P0, P0 + d, P0 + off, P0 + off + d + 1e-9 * rng.normal(size=3)))  # nearly parallel
        out.append((P0, P0 + d, P0 + d, P0 + d + off))  # sharing an end point
    return out


def test_segment_distance_against_dense_sampling():
    """The exact distance is never above the sampled minimum and never more than the sampling's
    resolution below it; the reported parameters give that distance."""
    rng = np.random.default_rng(39)
    cases = [tuple(rng.normal(size=(4, 3)) * rng.uniform(0.1, 3.0)) for _ in range(150)]
    cases += _special_segments(rng)
    P0, P1, Q0, Q1 = (np.array(x) for x in zip(*cases))
    d, s, t = segment_distance(P0, P1, Q0, Q1)
    assert ((s >= 0) & (s <= 1) & (t >= 0) & (t <= 1)).all()
    gap = P0 + s[:, None] * (P1 - P0) - Q0 - t[:, None] * (Q1 - Q0)
    np.testing.assert_allclose(np.linalg.norm(gap, axis=1), d, rtol=0, atol=1e-12)
    for k, (a0, a1, b0, b1) in enumerate(cases):
        sampled = _sampled_min(a0, a1, b0, b1)
        resolution = (np.linalg.norm(a1 - a0) + np.linalg.norm(b1 - b0)) / (2 * (N_SAMPLE - 1))
        assert d[k] <= sampled + 1e-12, k
        assert sampled <= d[k] + resolution + 1e-12, k


def test_crossing_segments_at_a_known_distance():
    """Two perpendicular segments crossing at their middles, h apart: distance h at s = t = 1/2;
    crossing at h = 0 they intersect."""
    for h in (0.0, 1e-3, 0.25):
        d, s, t = segment_distance([-1, 0, 0], [1, 0, 0], [0, -2, h], [0, 2, h])
        assert d == pytest.approx(h, abs=1e-15) and s == 0.5 and t == 0.5
    # skew lines whose closest points lie beyond the segments: the clamped end points
    d, s, t = segment_distance([0, 0, 0], [1, 0, 0], [3, -1, 1], [3, 1, 1])
    assert d == pytest.approx(np.hypot(2.0, 1.0)) and s == 1.0 and t == 0.5


def test_parallel_collinear_and_degenerate_cases():
    d, _, _ = segment_distance([0, 0, 0], [1, 0, 0], [0.5, 0.3, 0], [2, 0.3, 0])  # parallel, overlapping
    assert d == pytest.approx(0.3)
    d, s, t = segment_distance([0, 0, 0], [1, 0, 0], [2, 0.3, 0], [3, 0.3, 0])  # parallel, apart
    assert d == pytest.approx(np.hypot(1.0, 0.3)) and (s, t) == (1.0, 0.0)
    d, _, _ = segment_distance([0, 0, 0], [1, 0, 0], [0.5, 0, 0], [3, 0, 0])  # collinear, overlapping
    assert d == 0.0
    d, _, _ = segment_distance([0, 0, 0], [1, 0, 0], [-3, 0, 0], [-2, 0, 0])  # collinear, apart
    assert d == pytest.approx(2.0)
    d, s, t = segment_distance([0, 1, 0], [0, 1, 0], [-1, 0, 0], [1, 0, 0])  # a point over a segment
    assert d == pytest.approx(1.0) and t == pytest.approx(0.5)
    d, _, _ = segment_distance([0, 1, 0], [0, 1, 0], [0, 1, 0], [0, 1, 0])  # the same point
    assert d == 0.0


def test_rotation_and_translation_invariance():
    rng = np.random.default_rng(7)
    P0, P1, Q0, Q1 = rng.normal(size=(4, 200, 3))
    d, s, t = segment_distance(P0, P1, Q0, Q1)
    R = rotation_matrix(rng.normal(size=3))
    c = rng.normal(size=3) * 10
    moved = [x @ R.T + c for x in (P0, P1, Q0, Q1)]
    d2, s2, t2 = segment_distance(*moved)
    np.testing.assert_allclose(d2, d, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(s2, s, atol=1e-8)
    np.testing.assert_allclose(t2, t, atol=1e-8)


def test_whole_robot_moved_rigidly_has_the_same_interference():
    """The wall robot with fixed pulleys and the CoGiRo hull: anchors, pose and gravity-free
    geometry moved by one rigid motion give the same distances, chords and depths."""
    rng = np.random.default_rng(3)
    Q, c = rotation_matrix([0.3, -0.7, 1.1]), np.array([2.0, -1.0, 0.5])
    for path in (WALL, COGIRO):
        data = yaml.safe_load(path.read_text())
        for cab in data["cables"]:
            cab.pop("pulley", None)
        data["pulley"] = {"kind": "fixed", "h_m": 0.0, "r_p_m": 0.0}
        moved = copy.deepcopy(data)
        for cab in moved["cables"]:
            cab["A_m"] = (Q @ np.array(cab["A_m"], dtype=float) + c).tolist()
        robot, robot_m = robot_from_dict(data, "a"), robot_from_dict(moved, "b")
        p = rng.uniform(-0.5, 0.5, size=(20, 3)) + [0, 0, 1.5]
        rv = rng.normal(scale=0.4, size=(20, 3))
        R = rotation_matrix(rv)
        a = interference(robot, p, R=R)
        b = interference(robot_m, p @ Q.T + c, R=Q @ R)
        np.testing.assert_allclose(b.distance, a.distance, rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(b.depth, a.depth, atol=1e-12)
        np.testing.assert_allclose(b.length, a.length, atol=1e-12)
        assert (b.cc == a.cc).all() and (b.cp == a.cp).all()


def test_segment_through_a_cube():
    """A box of half-size 0.5 about the origin; the segment from (-1, 0.1, 0.2) to (1, 0.1, 0.2)
    enters at x = -0.5 (s = 1/4), leaves at x = 0.5 (s = 3/4); its deepest point is 0.3 m from the
    nearest face (z = 0.5)."""
    box = robot_from_dict(_box_robot([0.0, 0.0, 0.0], [0.5, 0.5, 0.5]), "box")
    faces = platform_faces(box)
    s_in, s_out, depth = clip_segments(np.array([-1, 0.1, 0.2]), np.array([1, 0.1, 0.2]), faces)
    assert (s_in, s_out) == pytest.approx((0.25, 0.75), abs=1e-15)
    assert depth == pytest.approx(0.3, abs=1e-15)
    # a diagonal through the centre: depth 0.5 at the centre, chord of length sqrt(3)
    s_in, s_out, depth = clip_segments(np.array([-1.0, -1, -1]), np.array([1.0, 1, 1]), faces)
    assert (s_in, s_out, depth) == pytest.approx((0.25, 0.75, 0.5), abs=1e-15)
    # missing the cube, lying in a face, and touching an edge: no depth
    for X0, X1 in (([-1, 0.6, 0], [1, 0.6, 0]), ([-1, 0.5, 0], [1, 0.5, 0]), ([-1, 0.5, 0.5], [1, 0.5, 0.5])):
        _, _, depth = clip_segments(np.array(X0, float), np.array(X1, float), faces)
        assert depth == 0.0


def _box_robot(centre, half, B=None):
    """Four fixed anchors high up, the platform a box (``platform.body``); attachments ``B``."""
    B = B or [[0.0, 0.0, 0.5]] * 4
    A = [[-3, -3, 4], [3, -3, 4], [3, 3, 4], [-3, 3, 4]]
    return {
        "platform": {"mass_kg": 10.0, "body": {"box": {"centre_m": centre, "half_m": half}}},
        "cable": {"young_modulus_Pa": 1e11, "diameter_m": 0.004, "max_tension_N": 1000.0},
        "pulley": {"kind": "fixed", "h_m": 0.0, "r_p_m": 0.0},
        "cables": [{"A_m": a, "B_m": b} for a, b in zip(A, B)],
    }


def test_cable_through_a_box_platform_reported():
    """Cables attached at the bottom of a cube to anchors above: each runs up through the cube;
    its chord, from the attachment (s_in = 0) to the top face, is the cube's height along it."""
    data = _box_robot(
        [0.0, 0.0, 0.5],
        [2.0, 2.0, 0.5],
        B=[[0.1, 0.1, 0.0], [-0.1, 0.1, 0.0], [-0.1, -0.1, 0.0], [0.1, -0.1, 0.0]],
    )
    robot = robot_from_dict(data, "box")
    res = interference(robot, np.array([[0.0, 0.0, 1.0]]))
    assert res.cp.all() and not res.free[0]
    B = np.array(data["cables"][0]["B_m"]) + [0, 0, 1.0]
    A = np.array(data["cables"][0]["A_m"], dtype=float)
    u = A - B
    s_top = 1.0 / u[2]  # the top face z = 1 + 1 of the platform at z = 1 (the sides are further)
    assert res.s_in[0, 0] == pytest.approx(0.0, abs=1e-15)
    assert res.s_out[0, 0] == pytest.approx(s_top)
    assert res.length[0, 0] == pytest.approx(s_top * np.linalg.norm(u))
    rep = report(res)
    assert [c["cable"] for c in rep["cable_platform"]] == [1, 2, 3, 4]
    assert set(rep["cable_platform"][0]) == {"cable", "length_m", "depth_m", "s_in", "s_out"}
    assert columns(res)["cp_cables"][0] == "1;2;3;4"


def test_touching_the_own_attachment_vertex_is_not_interference():
    """CoGiRo's hull at the identity, low in the frame: every cable leaves its attachment, a hull
    vertex, outward and upward (no depth), so only the vertex is touched; turned by 30 degrees
    about z, a cable runs into the hull from its vertex (depth > 0)."""
    robot = load_robot(COGIRO)
    assert platform_faces(robot) is not None
    res = interference(robot, np.array([[0.0, 0.0, 0.5]]))
    at_vertex = res.s_in[0] == 0.0
    assert at_vertex.any()  # the chord [0, 0]: the attachment itself
    assert (res.depth[0, at_vertex] <= DEPTH_TOL).all() and not res.cp[0, at_vertex].any()
    flat = copy.deepcopy(yaml.safe_load(COGIRO.read_text()))
    flat["platform"]["body"] = "none"
    assert interference(robot_from_dict(flat, "none"), np.array([[0.0, 0.0, 0.5]])).cp.sum() == 0


def test_a_cable_into_the_hull_from_its_vertex_interferes():
    """A tetrahedron platform whose cable 1 runs from its attachment (a vertex) across the body:
    depth > 0, s_in = 0; the other cables leave their vertices outward."""
    data = _box_robot([0, 0, 0], [1, 1, 1], B=[[0, 0, 0], [0.4, 0, 0], [0, 0.4, 0], [0, 0, 0.4]])
    data["platform"].pop("body")  # the default hull
    data["cables"][0]["A_m"] = [3, 3, 4]  # cable 1 from the origin vertex up through the body
    data["cables"][2]["A_m"] = [-3, -3, 4]
    robot = robot_from_dict(data, "tetra")
    res = interference(robot, np.array([[0.0, 0.0, 1.0]]))
    assert res.cp[0, 0] and res.s_in[0, 0] == 0.0 and res.depth[0, 0] > 1e-3
    assert not res.cp[0, 1:].any()


def test_wall_robot_crossing_pairs_at_home_with_fixed_pulleys():
    """The wall robot at (0, 0, 1.5) m, identity, fixed pulleys: the robot is symmetric under
    x -> -x and y -> -y (anchors and attachments), so a cable whose anchor and attachment lie on
    opposite sides of a mirror plane meets its mirror image there: those pairs, and only those,
    meet (distance 0)."""
    robot = with_pulleys(load_robot(WALL), kind="fixed")
    a = robot.arrays
    mirrors = set()
    for flip in (np.array([-1.0, 1, 1]), np.array([1.0, -1, 1])):
        for i in range(robot.m):
            for j in range(i + 1, robot.m):
                crosses = (a.A[i] @ (1 - flip)) * (a.b[i] @ (1 - flip)) < 0
                if crosses and np.allclose(a.A[i] * flip, a.A[j]) and np.allclose(a.b[i] * flip, a.b[j]):
                    mirrors.add((i + 1, j + 1))
    res = interference(robot, np.array([[0.0, 0.0, 1.5]]))
    rep = report(res)
    got = {tuple(c["cables"]) for c in rep["cable_cable"]}
    assert got == mirrors and len(got) == 6
    assert all(c["distance_m"] < 1e-12 for c in rep["cable_cable"])
    assert rep["shared"] == [] and rep["cable_platform"] == [] and not rep["interference_free"]
    assert rep["dmin_m"] < 1e-12 and tuple(rep["dmin_pair"]) in mirrors
    assert columns(res)["cc_pairs"][0] == ";".join(f"{i}-{j}" for i, j in sorted(mirrors))
    assert interference_free(robot, [0.0, 0.0, 1.5]) is False


def test_point_mass_has_no_cable_cable_interference():
    robot = load_robot(CDPR4)
    res = interference(robot, np.array([[0.1, 0.2, 1.0], [0.0, 0.0, 2.0]]))
    assert res.free.all() and len(res.pairs) == 0 and not res.has_body
    assert [(i, j, at) for i, j, at in res.shared] == [(i, j, "B") for i in range(4) for j in range(i + 1, 4)]
    rep = report(res, 1)
    assert rep["dmin_m"] is None and rep["dmin_pair"] is None and len(rep["shared"]) == 6


def test_shared_fixed_anchor_is_listed_and_not_tested():
    """Two fixed pulleys at the same anchor share D; two cables at the same attachment share B."""
    B = [[0.1, 0.1, 0.0], [-0.1, 0.1, 0.0], [-0.1, -0.1, 0.0], [-0.1, -0.1, 0.0]]
    data = _box_robot([0, 0, 0], [0.1, 0.1, 0.1], B=B)
    data["platform"]["body"] = "none"
    data["cables"][1]["A_m"] = data["cables"][0]["A_m"]
    robot = robot_from_dict(data, "shared")
    assert shared_pairs(robot) == [(0, 1, "D"), (2, 3, "B")]
    res = interference(robot, np.array([[0.0, 0.0, 1.0]]))
    assert {tuple(p) for p in res.pairs.tolist()} == {(0, 2), (0, 3), (1, 2), (1, 3)}


def test_hull_of_a_flat_platform_is_no_body():
    data = _box_robot([0, 0, 0], [1, 1, 1], B=[[0.2, 0, 0], [0, 0.2, 0], [-0.2, 0, 0], [0, -0.2, 0]])
    data["platform"]["body"] = "hull"
    assert platform_faces(robot_from_dict(data, "flat")) is None


def test_body_of_the_robot_file():
    data = _box_robot([0, 0, 0.1], ["10 cm", 0.2, 0.3])
    assert robot_from_dict(data, "r").platform.body == BoxBody((0.0, 0.0, 0.1), (0.1, 0.2, 0.3))
    assert robot_from_dict(yaml.safe_load(COGIRO.read_text()), "c").platform.body == "hull"
    bad = [
        ("hul", "platform.body"),
        ({"box": {"centre_m": [0, 0]}}, "platform.body.box.centre_m"),
        ({"box": {"centre_m": [0, 0, 0], "half_m": [0.1, 0.0, 0.1]}}, "platform.body.box.half_m"),
        ({"box": {"centre_m": [0, 0, 0]}}, "platform.body.box.half_m"),
        ({"sphere": 1}, "platform.body"),
    ]
    for body, key in bad:
        d = copy.deepcopy(data)
        d["platform"]["body"] = body
        with pytest.raises(CdprError) as exc:
            robot_from_dict(d, "r.yaml")
        msg = str(exc.value)
        assert "\n" not in msg and f"key '{key}'" in msg and msg.startswith("r.yaml"), msg


def test_non_finite_pose_refused():
    robot = load_robot(COGIRO)
    with pytest.raises(CdprError, match="finite"):
        interference(robot, np.array([[0.0, np.nan, 1.0]]))
    assert interference_free(robot, [0.0, np.nan, 1.0]) is None


def test_blocks_give_the_same_answer(monkeypatch):
    """Poses and chord depths are processed in blocks (memory): small blocks, the same arrays."""
    import cdpr.models.interference as itf

    robot = load_robot(COGIRO)
    rng = np.random.default_rng(5)
    p = rng.uniform([-6, -4, 0], [6, 4, 5], size=(300, 3))
    rv = rng.normal(scale=0.3, size=(300, 3))
    whole = interference(robot, p, rv)
    monkeypatch.setattr(itf, "POSE_BLOCK", 7)
    monkeypatch.setattr(itf, "DEPTH_BLOCK", 3)
    small = interference(robot, p, rv)
    for name in (
        "distance",
        "s",
        "cc",
        "cp",
        "s_in",
        "s_out",
        "length",
        "depth",
        "free",
        "dmin",
        "dmin_pair",
    ):
        np.testing.assert_array_equal(getattr(small, name), getattr(whole, name), err_msg=name)
    assert whole.cp.any() and whole.free.any()


def test_nearly_parallel_segments_crossing_at_a_known_distance():
    """Two 2 m segments 1e-6 rad apart that cross (seen along z) at their middles, h apart: the
    closest points are the middles, not an end (an edge candidate would give about 1e-6 m)."""
    for h in (0.0, 1e-9, 1e-4):
        d, s, t = segment_distance([-1, 0, 0], [1, 0, 0], [-1, -1e-6, h], [1, 1e-6, h])
        assert d == pytest.approx(h, abs=1e-15) and s == pytest.approx(0.5) and t == pytest.approx(0.5)
