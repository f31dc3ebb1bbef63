"""Interference in the uncertainty study (issue 39, docs/interference.md): a point where the nominal
robot's cables interfere at its solved pose is left out of every statistic (Monte Carlo, linearised,
Sobol, the dominant map) and counted in ``interfering_points``; a sample whose own robot interferes
at its solved pose is flagged (``interfering_full``), not left out. CoGiRo turned 0.6 rad about z
over a box inside its RW_C: 6 of the 27 grid poses have a cable through the platform; at the
identity none, and the tables are the statistics over every point."""

import copy
import os

import numpy as np
import pandas as pd
import pytest

from cdpr.analyses.uncertainty import PoseErrorModel, sample_stats
from cdpr.analyses.workspace import grid_points
from cdpr.models.interference import interference
from cdpr.parameters import parameter_values, robot_with_parameters
from cdpr.pipeline import uq
from cdpr.pipeline.study import Study, design_robot, load_study
from cdpr.robot import load_robot
from cdpr.solve import reached_answer, solve
from tests.conftest import ROOT

BOX = [-3.0, 3.0, -2.0, 2.0, 1.0, 3.5]  # inside CoGiRo's RW_C
TURN = [0.0, 0.0, 0.6]  # rad about z: the platform's hull meets some cables


@pytest.fixture(scope="module")
def spatial():
    cwd = os.getcwd()
    os.chdir(ROOT)
    try:
        yield load_study(ROOT / "config" / "studies" / "quick_spatial.yaml")
    finally:
        os.chdir(cwd)


def _study(st, rotvec):
    s = Study(copy.deepcopy(dict(st)))
    s.path, s.robot_models = st.path, st.robot_models
    s["rotvec_rad"] = rotvec
    return s


@pytest.fixture(scope="module")
def turned(spatial):
    return _study(spatial, TURN)


def _nominal_interfering(st, case):
    """Independently: the nominal robot solved at the grid's poses under the commanded lengths, and
    the interference of its cables at the solved poses."""
    m_ = uq.model(st, "SRopt", case, grid_points(BOX, st["uncertainty"]["monte_carlo"]["index_n"]))
    f = m_.feasible
    res = solve(m_.robot, m_.p[f], m_.rotvec[f], redundancy="physical", L0=m_.L[f])
    ok = res["status"] == "ok"
    bad = np.zeros(len(m_.p), dtype=bool)
    bad[np.flatnonzero(f)[ok]] = ~interference(m_.robot, res["P_s"][ok], res["rotvec_s"][ok]).free
    return m_, bad


@pytest.mark.parametrize("case", ["uncompensated", "compensated"])
def test_interfering_points_are_left_out_of_the_monte_carlo_and_counted(turned, case):
    m_, bad = _nominal_interfering(turned, case)
    assert bad.sum() == 6  # a cable through the turned platform's hull
    np.testing.assert_array_equal(m_.interfering(), bad)
    samples, points = uq.mc_shard(turned, "SRopt", case, BOX, 0)
    assert (samples.interfering_points == 6).all()
    np.testing.assert_array_equal(points.interfering.to_numpy(), bad)
    assert points.max_diff_m[bad].isna().all() and (points.n_disagree[bad] == 0).all()
    # the sample statistics are those of the 21 points kept
    th = uq.mc_parameters(turned, m_.robot, 0, len(samples))
    values, ok = m_.solve(th)
    kept = sample_stats(values["dp"][:, ~bad], ok[:, ~bad])
    every = sample_stats(values["dp"], ok)
    np.testing.assert_allclose(samples.index_full_m, kept.index_m, rtol=1e-12)
    np.testing.assert_array_equal(samples.not_ok_full, kept.not_ok)
    assert np.abs(kept.index_m - every.index_m).max() > 1e-6  # leaving them out changes the index
    # the linearised samples leave out the same points: the nominal row is the kept points' mean
    linear = uq.linear_samples(turned, "SRopt", case, BOX)
    assert (linear.interfering_points == 6).all()
    nom = linear[linear["sample"] == -1].iloc[0]
    np.testing.assert_allclose(nom.index_m, points.dp_nominal_m[~bad].mean(), rtol=1e-12)
    b = uq.bands(linear, samples)
    assert b.interfering_points.tolist() == [6, 6]
    assert pd.isna(b.interfering_full[0]) and b.interfering_full[1] == samples.interfering_full.sum()
    a = uq.agreement(samples, points, turned["uncertainty"]["monte_carlo"]["agree_tol_m"])
    assert a["n"] == len(samples)


def test_sobol_and_the_map_leave_them_out_and_the_path_flags_them(turned):
    indices, rows = uq.sobol(turned, "SRopt", "uncompensated", BOX)
    assert {"interfering_points", "interfering_full"} <= set(rows.columns)
    assert np.isfinite(indices.ST).any()
    m = uq.dominant_map(turned, "SRopt", "uncompensated")
    out = m.interfering.to_numpy()
    assert out.any() and (~out).any()
    assert (m.dominant[out] == "").all() and m.rms_m[out].isna().all() and m.dp_nominal_m[out].isna().all()
    assert (m.dominant[~out] != "").any()
    p = uq.path_bands(turned, "SRopt", "uncompensated")
    flagged = p.interfering.to_numpy()
    assert flagged.any() and (~flagged).any()
    assert np.isfinite(p.q50_m[flagged]).all()  # flagged, not left out
    assert ((p.interfering_share >= 0) & (p.interfering_share <= 1)).all()


def test_a_perturbed_robot_is_flagged_where_its_own_cables_interfere(spatial):
    """PoseErrorModel.solve(interference=True) against each sample's robot tested independently at
    its solved pose (the reached equilibrium where the restarts find several: one such pose here):
    anchors moved by up to 30 cm make some grid poses interfere."""
    robot = design_robot(spatial, spatial["doe"]["robot"], spatial["optimal"]["SRopt"])
    P = grid_points(BOX, 3)
    rv = np.array(TURN) * 0.95
    m_ = PoseErrorModel(robot, P, "uncompensated", redundancy="physical", rotvec=rv)
    th0 = parameter_values(robot)
    rng = np.random.default_rng(7)
    m = robot.m
    th = np.tile(th0, (4, 1))
    th[1:, 4 * m : 7 * m] += rng.uniform(-0.3, 0.3, size=(3, 3 * m))
    values, ok, hit = m_.solve(th, interference=True)
    for i, t in enumerate(th):
        r = robot_with_parameters(robot, t)
        res = reached_answer(r, solve(r, P, rv, redundancy="physical", L0=m_.L))  # the studies' answer
        good = res["status"] == "ok"
        expect = np.zeros(len(P), dtype=bool)
        expect[good] = ~interference(r, res["P_s"][good], res["rotvec_s"][good]).free
        np.testing.assert_array_equal(hit[i], expect)
    assert hit[1:].sum(axis=1).tolist() != [hit[0].sum()] * 3  # the anchors move the interference
    np.testing.assert_array_equal(m_.interfering(), hit[0])


def test_without_interference_the_statistics_are_over_every_point(spatial):
    """At the identity no pose of the box interferes: the counts are 0 and the statistics are the
    plain ones over every point (what the references keep)."""
    st = _study(spatial, None)
    samples, points = uq.mc_shard(st, "SRopt", "uncompensated", BOX, 0)
    assert (samples.interfering_points == 0).all() and not points.interfering.any()
    m_ = uq.model(st, "SRopt", "uncompensated", grid_points(BOX, st["uncertainty"]["monte_carlo"]["index_n"]))
    values, ok = m_.solve(uq.mc_parameters(st, m_.robot, 0, len(samples)))
    np.testing.assert_array_equal(samples.index_full_m, sample_stats(values["dp"], ok).index_m)


def test_a_point_mass_has_no_interference_to_test():
    """A point mass (the paper's studies): nothing is left out and its tables get no interference
    columns (``uq._rigid``), so they keep their bytes."""
    robot = load_robot(ROOT / "config" / "robots" / "cdpr4.yaml")
    assert robot.point_mass
    m_ = PoseErrorModel(robot, grid_points([-1.0, 1.0, -1.0, 1.0, 0.5, 1.5], 2), "uncompensated")
    assert not m_.interfering().any() and not uq._rigid(m_)


def test_the_summary_counts_what_the_uncertainty_study_left_out(tmp_path):
    from cdpr import table_io
    from cdpr.pipeline import summary_rows
    from cdpr.pipeline.results import rel_path

    b = pd.DataFrame(
        {
            "design": ["SRopt"] * 3,
            "case": ["uncompensated"] * 3,
            "method": ["linearised", "full", "all_parameters"],
            "interfering_points": [6, 6, 1],
            "interfering_full": pd.array([pd.NA, 2, 3], dtype="Int64"),
            "index_n": [3, 3, 2],
        }
    )
    p = tmp_path / rel_path("uncertainty", "bands")
    p.parent.mkdir(parents=True)
    table_io.write_table(b, p)
    rows = {r["quantity"]: r for r in summary_rows.left_out_rows(tmp_path)}
    r = rows["uncertainty over RW_C: interfering points left out"]
    assert r["ours"] == 7
    assert r["note"] == (
        "SRopt uncompensated Monte Carlo: 6 of 27; SRopt uncompensated Sobol: 1 of 8; "
        "sample points where the sample's robot interferes (flagged, kept): 5"
    )
