"""Compensated cable lengths (cdpr.analyses.compensation): exact round trip through the physical
equilibrium, Hooke's law, infeasible points, modulus mismatch."""

import numpy as np
import pytest

from cdpr.analyses.compensation import COMP_STATUSES, compensate, compensated_pose, rest_lengths
from cdpr.compiled.equilibrium import solve_points as solve_physical_fast
from cdpr.errors import CdprError
from cdpr.models.inverse import igm_e
from cdpr.models.statics import stretched_length
from cdpr.robot import read_yaml, robot_from_dict, with_pulleys, with_values
from cdpr.tables import to_frame
from tests.conftest import ROBOTS
from tests.models.test_equilibrium import mixed_robot
from tests.point_mass import solve_physical

rng = np.random.default_rng(23)
PTS = np.column_stack([rng.uniform(-2.0, 2.0, 80), rng.uniform(-2.0, 2.0, 80), rng.uniform(0.2, 4.0, 80)])


def robots(cdpr4):
    return {k: with_pulleys(cdpr4, kind=k) for k in ("fixed", "SR", "DR")} | {"mixed": mixed_robot()}


def test_rest_lengths_stretch_back_to_the_extended_lengths(cdpr4):
    L_TE = igm_e(cdpr4, PTS).L_TE
    t = rng.uniform(0, 5000, L_TE.shape)
    L0 = rest_lengths(L_TE, t, cdpr4.ES)
    assert (L0 < L_TE).all()
    assert np.abs(stretched_length(L0, t, cdpr4.ES) - L_TE).max() < 1e-14


@pytest.mark.parametrize("name", ["fixed", "SR", "DR", "mixed"])
@pytest.mark.parametrize("method", ["min_norm", "closed_form_improved", "subset"])
@pytest.mark.parametrize("solve", [solve_physical, solve_physical_fast], ids=["numpy", "compiled"])
def test_round_trip_is_exact(cdpr4, name, method, solve):
    """The physical equilibrium of the compensated lengths is p with the planned tensions, from a
    start 10 cm away (so Newton has to find it)."""
    r = robots(cdpr4)[name]
    comp = compensate(r, PTS, method=method)
    ok = comp["feasible"]
    assert ok.sum() > 40
    p = PTS[ok]
    res = solve(r, p, L0=comp["L0"][ok], P0=p + rng.normal(0, 0.06, p.shape))
    assert (res["status"] == "ok").all()
    assert res["dp"].max() < 1e-9
    planned = comp["t"][ok]
    assert (res["taut"] == (planned > 1e-6)).all()
    assert np.abs(np.nan_to_num(res["t"]) - planned).max() < 1e-6
    if method == "subset":
        assert (res["n_taut"] == 3).all()  # the extra cable rests exactly at its rest length


def test_compensated_pose_reports_the_residual_error(cdpr4):
    """Same robot: no error. Cables softer / stiffer than modelled: an error of the size of the
    stretch difference, and the taut cables follow."""
    data = read_yaml(ROBOTS / "cdpr4.yaml")
    for kind in ("SR", "DR"):
        model = with_pulleys(cdpr4, kind=kind)
        real = with_pulleys(
            with_values(robot_from_dict(data), E_cables=[80e9, 120e9, 95e9, 130e9]), kind=kind
        )
        same = compensated_pose(model, PTS)
        assert (same["status"] == "ok").sum() > 40
        assert np.nanmax(same["dp"]) < 1e-9
        off = compensated_pose(model, PTS, actual=real)
        ok = off["status"] == "ok"
        assert 1e-5 < np.median(off["dp"][ok]) < 0.01
        numpy = compensated_pose(model, PTS, actual=real, engine="numpy")
        np.testing.assert_array_equal(numpy["status"], off["status"])
        assert np.nanmax(np.abs(numpy["P_s"] - off["P_s"])) < 1e-9


def test_infeasible_points_are_flagged_and_not_solved(cdpr4):
    p = np.array([[0.0, 0.0, 2.0], [0.0, 0.0, 4.95], [2.45, 2.45, 0.5]])
    res = compensated_pose(cdpr4, p, t_max=3000.0)
    assert list(res["status"]) == ["ok", "infeasible", "infeasible"]
    assert np.isnan(res["P_s"][1:]).all() and np.isnan(res["L0"][1:]).all() and np.isnan(res["dp"][1:]).all()
    assert res["statuses"] == COMP_STATUSES
    df = to_frame(cdpr4, res, "physical")
    assert list(df["status"].astype(str)) == ["ok", "infeasible", "infeasible"]


def test_subset_follows_paper_mode(cdpr4):
    from cdpr.compiled.subsets import solve_points_fast

    r = with_pulleys(cdpr4, kind="SR")
    comp = compensate(r, PTS, method="subset")
    paper = solve_points_fast(r, PTS)
    np.testing.assert_array_equal(comp["subset"], paper["subset"])
    ok = comp["feasible"]
    rows = np.arange(len(PTS))[ok]
    # the cable outside the subset carries nothing and rests at its extended length
    other = np.array([sorted(set(range(4)) - set(s))[0] for s in comp["subset"][ok]])
    assert (comp["t"][rows, other] == 0).all()
    assert (comp["L0"][rows, other] == comp["L_TE"][rows, other]).all()
    same = compensate(r, PTS, method="subset", engine="numpy")
    np.testing.assert_array_equal(same["subset"], comp["subset"])


def test_unknown_method(cdpr4):
    with pytest.raises(ValueError, match="allowed"):
        compensate(cdpr4, PTS[:2], method="magic")
    with pytest.raises(CdprError, match="unknown engine 'gpu'; allowed: compiled, numpy"):
        compensated_pose(cdpr4, PTS[:2], engine="gpu")
