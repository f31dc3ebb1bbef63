"""The uncertainty study's experiments on a robot solved as a pose (cdpr.pipeline.uq, responses ‖δp‖
and δφ) on the quick spatial study: shards reproducible whatever their number, the point mass's
columns kept (uq.bands and uq.agreement read the tables) with δφ beside them, the linearised nominal row equal to the full solves of the nominal
robot, and the compensated nominal robot a round trip."""

import copy
import os
import shutil

import numpy as np
import pandas as pd
import pytest

from cdpr.errors import ConfigError
from cdpr.pipeline import summary, uq
from cdpr.pipeline.study import Study, load_study
from tests.conftest import ROOT

QUICK_SPATIAL = ROOT / "config" / "studies" / "quick_spatial.yaml"
BOX = [-3.0, 3.0, -2.0, 2.0, 1.0, 3.5]  # inside CoGiRo's RW_C


@pytest.fixture(scope="module")
def spatial():
    cwd = os.getcwd()
    os.chdir(ROOT)
    try:
        yield load_study(QUICK_SPATIAL)
    finally:
        os.chdir(cwd)


def _study(st, **mc):
    s = Study(copy.deepcopy(dict(st)))
    s.path, s.robot_models = st.path, st.robot_models
    s["uncertainty"]["monte_carlo"].update(mc)
    return s


def test_spatial_monte_carlo_reproducible_across_shard_counts(spatial):
    one = uq.mc_shard(_study(spatial, full_samples=4, shards=1), "SRopt", "uncompensated", BOX, 0)[0]
    two = pd.concat(
        [
            uq.mc_shard(_study(spatial, full_samples=4, shards=2), "SRopt", "uncompensated", BOX, k)[0]
            for k in (0, 1)
        ],
        ignore_index=True,
    )
    pd.testing.assert_frame_equal(one, two)
    assert one["index_phi_full_rad"].nunique() == 4 and (one["index_phi_full_rad"] > 0).all()


@pytest.mark.parametrize("case", ["uncompensated", "compensated"])
def test_spatial_tables_keep_uq_columns_and_the_nominal_row_is_the_full_solve(spatial, case):
    samples, points = uq.mc_shard(spatial, "SRopt", case, BOX, 0)
    linear = uq.linear_samples(spatial, "SRopt", case, BOX)
    b = uq.bands(linear, samples)  # without Saltelli's rows: ‖δp‖'s two rows, no δφ band
    assert list(b.method) == ["linearised", "full"] and np.isfinite(b.index_q50_m).all()
    assert "index_phi_q50_rad" not in b
    a = uq.agreement(samples, points, spatial["uncertainty"]["monte_carlo"]["agree_tol_m"])
    assert a["n"] == len(samples)
    # sample -1: the linearisation's nominal answer is the nominal robot's full solve on the same grid
    nom = linear[linear["sample"] == -1].iloc[0]
    np.testing.assert_allclose(nom.index_m, points.dp_nominal_m.mean(), rtol=1e-12)
    np.testing.assert_allclose(nom.index_phi_rad, points.dphi_nominal_rad.mean(), rtol=1e-12)
    phi = uq.bands(linear, samples, rows=linear[linear["sample"] >= 0])
    assert list(phi.method) == ["linearised", "full", "all_parameters"]
    assert (phi.index_phi_min_rad <= phi.index_phi_max_rad).all() and np.isfinite(phi.index_phi_q50_rad).all()
    assert {"max_index_phi_diff_rad", "max_point_phi_diff_rad"} <= set(a)
    if case == "compensated":  # compensated lengths hold the nominal robot at the pose
        assert nom.index_m < 1e-8 and nom.index_phi_rad < 1e-8
        assert (samples.index_full_m > 1e-5).all()  # the per-cable moduli move it
    else:
        assert nom.index_m > 0.05 and nom.index_phi_rad > 1e-3  # CoGiRo's L_TS error: 0.1-0.2 m


def test_spatial_path_bands_bracket_their_median(spatial):
    b = uq.path_bands(spatial, "SRopt", "uncompensated")
    assert (b.ok_share == 1).all()
    for q in ("_m", "_phi_rad"):
        assert (b[f"q05{q}"] <= b[f"q50{q}"]).all() and (b[f"q50{q}"] <= b[f"q95{q}"]).all()


def test_spatial_sobol_covers_both_responses_and_every_declared_driver(spatial):
    indices, rows = uq.sobol(spatial, "SRopt", "uncompensated", BOX)
    outputs = set(indices.output)
    assert {"index", "index_phi", "dp@(0, 0, 2)", "dphi@(0, 0, 2)"} == outputs
    groups = set(indices[indices.level == "group"].name)
    assert groups == {"E", "d", "A", "M"}
    assert {"index_m", "index_phi_rad"} <= set(rows.columns)
    assert len(rows) == 2 * spatial["uncertainty"]["sobol"]["base_samples"]


def test_spatial_dominant_map_names_a_driver_for_each_response(spatial):
    m = uq.dominant_map(spatial, "SRopt", "uncompensated")
    ok = m.dominant != ""
    assert ok.any() and (m.dominant_phi[ok] != "").all()
    assert ((m.share[ok] > 0) & (m.share[ok] <= 1)).all() and (m.rms_phi_rad[ok] > 0).all()


def test_summary_rows_of_the_spatial_uncertainty_study(spatial, tmp_path):
    """results/<study>/summary: per design and case the median indices of ‖δp‖ and δφ and the largest
    total Sobol index of each response (group and parameter), read from the reference tables of
    tests/reference/quick_spatial/uncertainty/."""
    ref = ROOT / "tests" / "reference" / "quick_spatial" / "uncertainty"
    (tmp_path / "uncertainty").mkdir()
    for name in ("bands.csv", "sobol.csv"):
        shutil.copy(ref / name, tmp_path / "uncertainty" / name)
    rows = pd.DataFrame(summary._uq_spatial_rows(spatial, tmp_path))
    sob = pd.read_csv(ref / "sobol.csv")
    for case in ("uncompensated", "compensated"):
        for what, out in (("‖δp‖", "index"), ("δφ", "index_phi")):
            g = sob[(sob.case == case) & (sob.output == out) & (sob.level == "group")]
            r = rows[
                rows.quantity == f"SRopt {case} largest total Sobol index on the index of {what} (group)"
            ]
            assert len(r) == 1 and r.ours.iloc[0] == g.ST.max()
            assert r.note.iloc[0].startswith(g.loc[g.ST.idxmax(), "name"] + ";")
        band = pd.read_csv(ref / "bands.csv")
        b = band[(band.case == case) & (band.method == "linearised")].iloc[0]
        r = rows[rows.quantity == f"SRopt {case} index of δφ under per-cable E (median)"]
        np.testing.assert_allclose(r.ours.iloc[0], b.index_phi_q50_rad * 1e3)
        assert (r.unit == "mrad").all()


# ---- the attachments b_i and the centre of mass c as the study's uncertain parameters ------------
RIGID_KEYS = {
    "attachment_offset_m": {"dist": "uniform", "low": -0.001, "high": 0.001, "per_cable": True},
    "com_offset_m": {"dist": "normal", "mean": 0.0, "sd": 0.003, "low": -0.009, "high": 0.009},
}


@pytest.fixture(scope="module")
def rigid(spatial):
    s = _study(spatial, vary=["young_modulus_Pa", "attachment_offset_m", "com_offset_m"], full_samples=3)
    s["uncertainty"]["parameters"].update(copy.deepcopy(RIGID_KEYS))
    return s


def test_rigid_platform_keys_run_through_the_spatial_uncertainty_study(rigid):
    """With attachment_offset_m and com_offset_m declared and varied: the Monte Carlo's full solves
    and the linearised propagation of the same samples agree (within the study's tolerance on
    ‖δp‖), the linearised nominal row is the nominal robot's full solve, and Sobol and the dominant
    map name the b and c drivers and groups."""
    samples, points = uq.mc_shard(rigid, "SRopt", "uncompensated", BOX, 0)
    assert (samples["index_full_m"] > 0).all()
    assert (points["max_diff_m"] < rigid["uncertainty"]["monte_carlo"]["agree_tol_m"]).all()
    linear = uq.linear_samples(rigid, "SRopt", "uncompensated", BOX)
    nom = linear[linear["sample"] == -1].iloc[0]
    np.testing.assert_allclose(nom.index_m, points.dp_nominal_m.mean(), rtol=1e-12)
    lin = linear[linear["sample"] >= 0].reset_index(drop=True)
    np.testing.assert_allclose(lin.index_m[: len(samples)], samples.index_full_m, rtol=2e-2)
    indices, _ = uq.sobol(rigid, "SRopt", "uncompensated", BOX)
    assert {"b", "c"} <= set(indices[indices.level == "group"].name)
    assert {"b_1_x", "c_z"} <= set(indices[indices.level == "parameter"].name)
    m = uq.dominant_map(rigid, "SRopt", "uncompensated")
    assert (m.dominant != "").any()


def test_a_point_mass_study_refuses_the_rigid_platform_keys_in_one_line(tmp_path):
    import yaml

    src = ROOT / "config" / "studies" / "quick.yaml"
    data = yaml.safe_load(src.read_text(encoding="utf-8"))
    data["robots"] = {k: str(ROOT / v) for k, v in data["robots"].items()}
    data["uncertainty"]["parameters"]["com_offset_m"] = RIGID_KEYS["com_offset_m"]
    path = tmp_path / "study.yaml"
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    with pytest.raises(ConfigError) as err:
        load_study(path)
    msg = str(err.value)
    assert "\n" not in msg and "uncertainty.parameters.com_offset_m" in msg and "point mass" in msg
