"""Compensation with heavy cables (issue 38): the sag-consistent tension distribution (a fixed point
of the bounded minimum-norm distribution whose wrench matrix holds the catenaries' unit end forces
at B_i) and its rest lengths, tested by the round trip through the heavy direct model started away
from the pose (<= 1e-9 m, 1e-9 rad) on a point mass (CDPR4 with a 4 mm cable) and on CoGiRo, by
the tension bounds at B_i, by the w = 0 limit (today's massless compensation) and by the fixed
point's defining property."""

import numpy as np
import pytest

from cdpr.analyses.compensation import compensate, compensated_pose, heavy_distribution
from cdpr.errors import CdprError
from cdpr.models import equilibrium
from cdpr.models.cables import HeavyCables
from cdpr.models.platform import pose_arrays
from cdpr.robot import load_robot, with_pulleys

RHO = 0.0631  # [kg/m] a 4 mm steel cable
P4 = np.array([[0.3, -0.5, 2.0], [1.5, 1.2, 3.5], [0.0, 0.0, 1.0], [-1.8, 0.9, 4.2]])
PC = np.array([[0.0, 0.0, 1.5], [1.0, 1.0, 1.5], [0.0, 0.0, 1.5], [-3.0, 2.0, 2.5]])
RC = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [np.radians(15.0), 0.0, 0.0], [0.05, -0.1, 0.2]])


@pytest.fixture(scope="module")
def cdpr4_heavy():
    return load_robot("config/robots/cdpr4.yaml", linear_density=RHO)


@pytest.fixture(scope="module")
def cogiro_heavy():
    return load_robot("config/robots/cogiro_massless.yaml", linear_density=RHO)


@pytest.mark.parametrize("kind", ["SR", "DR", "fixed"])
def test_point_mass_round_trip_from_away(cdpr4_heavy, kind):
    r = with_pulleys(cdpr4_heavy, kind=kind)
    c = compensate(r, P4)
    assert c["feasible"].all()
    assert (c["iterations"] >= 2).all() and (c["iterations"] <= 20).all()
    res = equilibrium.solve(r, P4, L0=c["L0"], P0=P4 + [0.05, -0.04, 0.03])
    assert (res["status"] == "ok").all()
    assert np.linalg.norm(res["P_s"] - P4, axis=1).max() <= 1e-9
    np.testing.assert_allclose(res["t_B"], c["t"], rtol=1e-8)


def test_rigid_platform_round_trip_from_away(cogiro_heavy):
    c = compensate(cogiro_heavy, PC, rotvec=RC)
    assert c["feasible"].all()
    res = equilibrium.solve(cogiro_heavy, PC, RC, L0=c["L0"], P0=PC + [0.03, -0.02, 0.04])
    assert (res["status"] == "ok").all()
    assert np.linalg.norm(res["P_s"] - PC, axis=1).max() <= 1e-9
    assert res["dphi"].max() <= 1e-9
    np.testing.assert_allclose(res["t_B"], c["t"], rtol=1e-8)


def test_sag_changes_the_distribution_and_lengths(cogiro_heavy):
    massless = load_robot("config/robots/cogiro_massless.yaml")
    a, b = compensate(massless, PC, rotvec=RC), compensate(cogiro_heavy, PC, rotvec=RC)
    # the cables' weight is carried: the tensions at B differ from the massless ones by newtons
    assert np.abs(b["t"] - a["t"]).max() > 1.0
    assert np.abs(b["L0"] - a["L0"]).max() > 1e-6


def test_fixed_point_is_the_min_norm_of_its_own_wrench_matrix(cogiro_heavy):
    p, R = pose_arrays(PC, RC)
    h = heavy_distribution(cogiro_heavy, p, R)
    again = heavy_distribution(cogiro_heavy, p, R, t0=h["t"])
    assert (again["iterations"] == 1).all()
    np.testing.assert_allclose(again["t"], h["t"], rtol=1e-11)
    # the catenaries' end forces at B balance the platform's weight at the desired pose
    out = HeavyCables(cogiro_heavy).evaluate(p, R, h["L0"], p, jacobian=False)
    mg = cogiro_heavy.platform.mass * cogiro_heavy.platform.g
    assert np.abs(out["F"]).max() <= 1e-8 * mg and np.abs(out["M"]).max() <= 1e-8 * mg


def test_tension_bounds_apply_at_B(cdpr4_heavy):
    c0 = compensate(cdpr4_heavy, P4[:1])
    t_min = float(np.sort(c0["t"][0])[0]) + 50.0  # above the least tension: that cable is pinned
    c = compensate(cdpr4_heavy, P4[:1], t_min=t_min)
    assert c["feasible"].all()
    assert c["t"].min() >= t_min - 1e-6 and np.isclose(c["t"].min(), t_min, rtol=0, atol=1e-6)
    res = equilibrium.solve(cdpr4_heavy, P4[:1], L0=c["L0"])
    assert np.isclose(res["t_B"].min(), t_min, rtol=1e-8)
    t_max = float(c0["t"].max()) - 50.0
    d = compensate(cdpr4_heavy, P4[:1], t_max=t_max)
    assert not d["feasible"].any() or d["t"].max() <= t_max + 1e-6


def test_weightless_through_the_heavy_path_is_todays_compensation(cdpr4):
    c = compensate(cdpr4, P4)
    p, R = pose_arrays(P4)
    h = heavy_distribution(cdpr4, p, R)
    assert (h["iterations"] == 1).all()
    np.testing.assert_allclose(h["t"], c["t"], rtol=1e-12)
    assert np.abs(h["L0"] - c["L0"]).max() <= 1e-12


def test_compensated_pose_reports_heavy_cables(cdpr4_heavy):
    o = compensated_pose(cdpr4_heavy, np.vstack([P4[:2], [[0.0, 0.0, 4.999]]]))
    assert list(o["status"]) == ["ok", "ok", "infeasible"]
    assert np.nanmax(o["dp"]) <= 1e-9
    assert (o["sag_max"][:2] > 1e-4).all() and np.isnan(o["sag_max"][2])
    assert (o["cable_status"][2] == "infeasible").all()
    np.testing.assert_allclose(o["planned_cables"]["sag"][:2], o["sag"][:2], rtol=1e-6)


def test_subset_is_refused_with_heavy_cables(cdpr4_heavy):
    with pytest.raises(CdprError, match="subset"):
        compensate(cdpr4_heavy, P4, method="subset")
