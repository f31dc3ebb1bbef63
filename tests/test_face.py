"""The public face (``cdpr.__all__``) on the robots users have: every function that takes a robot
and points answers a rigid platform's poses (N, 6) or positions (N, 3) with the 6-DoF models, or
refuses them in one line naming what to call instead; none answers a rigid platform with the
point-mass model (issue 17: "the library's face takes poses (N, 6) or positions (N, 3)")."""

import inspect

import numpy as np
import pytest

import cdpr
from cdpr.errors import CdprError
from cdpr.models.inverse import L_TS, pose_state
from cdpr.models.platform import pose_arrays
from cdpr.models.tension_distribution import compensated_lengths
from tests.conftest import ROBOTS

P = np.array([[0.0, 0.0, 2.0], [1.0, 1.0, 1.5]])
RV = np.array([[0.1, 0.0, 0.0], [0.0, 0.2, 0.1]])


@pytest.fixture(scope="module")
def cogiro():
    return cdpr.load_robot(ROBOTS / "cogiro_massless.yaml")


def _takes_robot_and_points(name):
    f = getattr(cdpr, name)
    if not callable(f) or isinstance(f, type):
        return False
    try:
        params = list(inspect.signature(f).parameters)
    except (TypeError, ValueError):
        return False
    return params[:2] in (["robot", "p"], ["robot", "P"])


FUNCTIONS = [n for n in cdpr.__all__ if n != "__version__" and _takes_robot_and_points(n)]


def test_the_face_lists_its_point_functions():
    assert {"L_TS", "igm_e", "degm_e", "solve_points"} <= set(FUNCTIONS)
    assert {"solve_table", "sensitivities", "compensate", "compensated_pose"} <= set(FUNCTIONS)


@pytest.mark.parametrize("name", FUNCTIONS)
@pytest.mark.parametrize("poses", [False, True], ids=["positions", "poses"])
def test_every_point_function_answers_a_rigid_platform_or_refuses_it(cogiro, name, poses):
    """A rigid platform (CoGiRo: attachments b_i): an answer or one CdprError line naming what to call."""
    pts = np.hstack([P, RV]) if poses else P
    try:
        getattr(cdpr, name)(cogiro, pts)
    except CdprError as e:
        msg = str(e)
        assert "\n" not in msg and ("use " in msg or " go to " in msg or "physical" in msg), msg


def test_standard_and_extended_lengths_at_poses(cogiro):
    p, R = pose_arrays(P, RV)
    B, st = pose_state(cogiro, p, R)
    want = L_TS(cogiro, p, R=R)
    assert np.array_equal(cdpr.L_TS(cogiro, P, RV), want)
    assert np.array_equal(cdpr.L_TS(cogiro, np.hstack([P, RV])), want)
    assert np.array_equal(cdpr.igm_e(cogiro, P, RV).L_TE, st.L_TE)
    # positions alone: the identity orientation, each cable at its own attachment point
    p0, R0 = pose_arrays(P)
    assert np.array_equal(cdpr.L_TS(cogiro, P), L_TS(cogiro, p0, R=R0))
    assert not np.allclose(cdpr.L_TS(cogiro, P), np.linalg.norm(P[:, None] - cogiro.A, axis=-1) + cogiro.d)


def test_point_mass_lengths_are_the_paper_formula():
    r4 = cdpr.load_robot(ROBOTS / "cdpr4.yaml")
    grid = np.random.default_rng(0).uniform([-2, -2, 0.5], [2, 2, 3], (7, 5, 3))  # any leading shape
    want = np.linalg.norm(grid[..., None, :] - r4.A, axis=-1) + r4.d
    assert np.array_equal(cdpr.L_TS(r4, grid), want)
    assert cdpr.igm_e(r4, grid).L_TE.shape == (7, 5, 4)
    # an orientation plays no part on a point mass
    assert np.array_equal(cdpr.L_TS(r4, np.hstack([P, RV])), cdpr.L_TS(r4, P))


def test_compensation_at_poses_round_trip(cogiro):
    """cdpr.compensate / compensated_pose on a rigid platform: the 6-DoF compensated lengths, and
    the platform commanded with them settles on the pose (1e-9 m, 1e-9 rad), by either engine."""
    c = cdpr.compensate(cogiro, np.hstack([P, RV]))
    assert np.array_equal(c["L0"], compensated_lengths(cogiro, P, RV)["L0"], equal_nan=True)
    for engine in ("compiled", "numpy"):
        res = cdpr.compensated_pose(cogiro, P, rotvec=RV, engine=engine)
        assert list(res["status"]) == ["ok", "ok"]
        assert res["dp"].max() < 1e-9 and res["dphi"].max() < 1e-9
        assert np.array_equal(res["rotvec"], RV)
    with pytest.raises(
        CdprError, match="compensation method 'subset'.* use closed_form, closed_form_improved, min_norm"
    ):
        cdpr.compensate(cogiro, P, method="subset")


def test_compensation_where_no_distribution_exists_is_infeasible():
    """A 4-cable 6-DoF platform tilted: no tension distribution holds it; nothing is solved there."""
    h4 = cdpr.load_robot(ROBOTS / "hang4_6dof.yaml")
    res = cdpr.compensated_pose(h4, P, rotvec=[0.3, 0.0, 0.0])
    assert list(res["status"]) == ["infeasible", "infeasible"]
    assert np.isnan(res["P_s"]).all() and np.isnan(res["dphi"]).all() and np.isnan(res["L0"]).all()
