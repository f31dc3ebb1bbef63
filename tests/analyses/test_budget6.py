"""Error budget on a rigid 6-DoF platform (cdpr.analyses.budget, the 6-DoF path): on CoGiRo at a few
poses, no effect gives no error and compensating everything gives none (position and orientation);
the point-mass CDPR4 forced through the 6-DoF path equals today's point-mass budget; turning the
whole robot about the vertical (gravity unchanged) turns δp and δφ with it."""

import dataclasses

import numpy as np
import pytest

from cdpr.analyses import budget
from cdpr.analyses.workspace import grid_points
from cdpr.models.platform import rotation_matrix
from cdpr.robot import load_robot, with_pulleys
from tests.conftest import ROBOTS

#: Poses inside CoGiRo's frame where Table 1's drum can pay every cable out (l_pm <= 10.27 m).
P = np.array([[0.0, 0.0, 2.0], [0.5, -0.5, 2.5], [-0.5, 0.5, 2.8]])
#: Their orientations: identity, 0.03 rad about x, 0.05 rad about z.
RV = np.array([[0.0, 0.0, 0.0], [0.03, 0.0, 0.0], [0.0, 0.0, 0.05]])
#: The numpy reference of the 6-DoF solve (the compiled twin is tested equal to it to 1e-9 m and rad).
ENGINE = "numpy"


@pytest.fixture(scope="module", params=["SR", "DR"])
def design(request):
    h = 0.05 if request.param == "SR" else 0.075
    return with_pulleys(load_robot(ROBOTS / "cogiro_massless.yaml"), kind=request.param, h=h, r_p=0.05)


@pytest.fixture(scope="module")
def result(design):
    return budget.error_budget(design, P, 100.0, rotvec=RV, engine=ENGINE)


def test_every_entry_has_position_and_orientation_errors(result):
    assert set(result) == {*budget.variants(), "interaction"}
    for k, r in result.items():
        assert r["dp"].shape == (3, 3) and r["dphi"].shape == (3, 3), k
        assert (r["status"] == "ok").all(), (k, r["status"])


def test_no_effect_gives_no_error(design, result):
    """Fixed exit points, rigid cables, an exact drum: the standard model is exact. What is left is
    the stretch of the E x RIGID cables (E -> infinity), which falls as 1 / RIGID."""
    r = result["none"]
    a = np.linalg.norm(r["dp"], axis=1)
    b = np.linalg.norm(r["dphi"], axis=1)
    assert a.max() < 1e-7 and b.max() < 1e-8
    old = budget.RIGID
    try:
        budget.RIGID = old * 100
        stiff = budget.variant(design, P, (), (), 100.0, rotvec=RV, engine=ENGINE)
    finally:
        budget.RIGID = old
    assert np.linalg.norm(stiff["dp"], axis=1).max() < 1e-9
    assert np.linalg.norm(stiff["dphi"], axis=1).max() < 1e-9
    np.testing.assert_allclose(np.linalg.norm(stiff["dp"], axis=1) * 100, a, rtol=0.05)


def test_compensating_every_effect_gives_no_error(result):
    r = result["compensated_all"]
    assert np.linalg.norm(r["dp"], axis=1).max() < 1e-9
    assert np.linalg.norm(r["dphi"], axis=1).max() < 1e-9


def test_each_effect_moves_and_turns_the_platform(result):
    for k in budget.EFFECTS:
        assert np.linalg.norm(result[k]["dp"], axis=1).min() > 1e-4, k
        assert np.linalg.norm(result[k]["dphi"], axis=1).min() > 1e-5, k
    # the pulleys dominate CoGiRo's position error (docs/spatial.md: 0.12-0.21 m under L_TS)
    n = {k: np.linalg.norm(result[k]["dp"], axis=1).mean() for k in budget.EFFECTS}
    assert max(n, key=n.get) == "pulley"


def test_interaction_and_summary_of_the_orientation(result):
    s = sum(result[k]["dphi"] for k in budget.EFFECTS)
    np.testing.assert_allclose(result["interaction"]["dphi"], result["all"]["dphi"] - s, atol=0)
    t = budget.summarise(result).set_index("entry")
    assert list(t.columns[-2:]) == ["mean_rad", "max_rad"]
    for k in result:
        a = np.linalg.norm(result[k]["dphi"], axis=1)
        assert t.loc[k, "mean_rad"] == pytest.approx(a.mean(), rel=1e-12, abs=1e-300)
    total = t.loc[[*budget.EFFECTS, "interaction"], "share_m"].sum()
    assert total == pytest.approx(t.loc["all", "mean_m"], rel=1e-12)


def test_point_mass_through_the_6dof_path_equals_the_point_mass_budget(cdpr4):
    """CDPR4 (b = 0, c = 0) given an orientation goes through the 6-DoF inverse, tension_distribution's
    compensation and the 6-DoF solver: the same budget as today's point-mass path to 1e-9 m."""
    d = with_pulleys(cdpr4, kind="SR", h=0.1, r_p=0.0665)
    pts = grid_points([-2.32, 2.32, -2.32, 2.32, 0.0, 3.73], 3)
    a = budget.error_budget(d, pts, engine=ENGINE)  # the numpy references of both solvers
    b = budget.error_budget(d, pts, rotvec=np.zeros(3), engine=ENGINE)
    assert "dphi" not in a["all"] and "mean_rad" not in budget.summarise(a)
    for k in a:
        np.testing.assert_array_equal(a[k]["status"], b[k]["status"])
        ok = a[k]["status"] == "ok"
        assert ok.sum() > 10, k
        np.testing.assert_allclose(b[k]["dp"][ok], a[k]["dp"][ok], atol=1e-9, rtol=0, err_msg=k)
        assert np.abs(b[k]["dphi"][ok]).max() == 0.0  # a point has no orientation


def _turned(robot, Q):
    """``robot`` turned by Q about the vertical: anchors, attachments, centre of mass and pulley
    frames (the zero of each swivel angle turned too); gravity (-z) is unchanged."""
    zero = tuple(Q @ [1.0, 0.0, 0.0])
    cables = tuple(
        dataclasses.replace(
            c,
            A=tuple(Q @ c.A),
            B=tuple(Q @ c.B),
            pulley=dataclasses.replace(c.pulley, axis=tuple(Q @ c.pulley.axis), zero=zero),
        )
        for c in robot.cables
    )
    platform = dataclasses.replace(robot.platform, com=tuple(Q @ robot.platform.com))
    return dataclasses.replace(robot, cables=cables, platform=platform)


def test_turning_the_robot_about_the_vertical_turns_the_errors(design):
    Q = rotation_matrix(np.array([0.0, 0.0, 0.7]))
    a = budget.variant(design, P, budget.EFFECTS, (), 100.0, engine=ENGINE)
    b = budget.variant(_turned(design, Q), P @ Q.T, budget.EFFECTS, (), 100.0, engine=ENGINE)
    assert (a["status"] == "ok").all() and (b["status"] == "ok").all()
    np.testing.assert_allclose(b["dp"], a["dp"] @ Q.T, atol=1e-9)
    np.testing.assert_allclose(b["dphi"], a["dphi"] @ Q.T, atol=1e-9)
