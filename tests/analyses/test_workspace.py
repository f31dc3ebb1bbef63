"""cdpr.analyses.workspace: grids, shards, voxel volumes and the largest box of a mask."""

import numpy as np
import pandas as pd
import pytest

from cdpr.analyses import workspace
from cdpr.errors import CdprError


def grid_table(n, box, ok):
    P = workspace.grid_points(box, n)
    return pd.DataFrame(
        {
            "x": P[:, 0],
            "y": P[:, 1],
            "z": P[:, 2],
            "dp": np.zeros(len(P)),
            "status": np.where(ok(P), "ok", "slack"),
        }
    )


def test_grid_points_cell_centres_and_slices():
    box = [0, 1, 0, 2, 0, 4]
    P = workspace.grid_points(box, 2)
    assert P.shape == (8, 3)
    assert sorted(set(P[:, 2])) == [1.0, 3.0] and P[0].tolist() == [0.25, 0.5, 1.0]
    parts = [workspace.grid_points(box, 3, *workspace.shard_range(27, k, 4)) for k in range(4)]
    np.testing.assert_array_equal(np.vstack(parts), workspace.grid_points(box, 3))
    with pytest.raises(CdprError):
        workspace.check_box([0, 1, 1, 0, 0, 1])


def test_voxel_volume_of_a_ball():
    """V_L of a ball of radius 1 in a 2 m cube: 4/3 pi within the reported voxel error."""
    n, box = 40, [-1, 1, -1, 1, -1, 1]
    df = grid_table(n, box, lambda P: np.linalg.norm(P, axis=1) <= 1.0)
    v = workspace.error_limited_volume(df, n, box, limit=1.0, envelope_volume=8.0)
    assert abs(v["V_L"] - 4 / 3 * np.pi) <= v["V_L_err"]
    assert v["R_V"] == pytest.approx(v["V_L"] / 8.0)


def test_largest_box_of_a_known_mask():
    mask = np.zeros((6, 7, 8), dtype=bool)
    mask[1:4, 2:7, 3:8] = True  # 3 x 5 x 5 = 75 voxels
    mask[5, 0, 0] = True  # a stray voxel
    count, cells = workspace.largest_box(mask)
    assert count == 75 and cells == (1, 3, 2, 6, 3, 7)
    b = workspace.box_from_cells([0, 6, 0, 6, 0, 6], 6, (1, 3, 2, 4, 0, 5))
    assert b == pytest.approx([1, 4, 2, 5, 0, 6])


def test_largest_box_in_a_grid_table_of_a_known_mask():
    """A feasible slab with a stray point, on a 6^3 grid of [0, 6]^3 m, half of it not ok: the box is
    the slab's ok part, with its bounds in m and volume in m^3."""
    n, box = 6, [0, 6, 0, 6, 0, 6]
    df = grid_table(n, box, lambda P: P[:, 2] > 2.0)  # ok for z > 2: cells k = 2..5
    P = df[["x", "y", "z"]].to_numpy()
    feasible = (P[:, 0] > 1) & (P[:, 0] < 4) & (P[:, 1] > 2) & (P[:, 2] < 5)  # x cells 1-3, y 2-5, z 0-4
    feasible |= (P[:, 0] > 5) & (P[:, 1] < 1) & (P[:, 2] > 5)  # a stray voxel (5, 0, 5)
    wf = workspace.largest_box_in(df, n, box, feasible)
    assert wf["count"] == 3 * 4 * 3 and wf["cells"] == (1, 3, 2, 5, 2, 4)
    assert wf["box"] == pytest.approx([1, 4, 2, 6, 2, 5]) and wf["volume_m3"] == pytest.approx(36.0)
    assert wf["admissible_m3"] == pytest.approx(36.0 + 1.0)
    none = workspace.largest_box_in(df, n, box, np.zeros(len(df), dtype=bool))
    assert none["count"] == 0 and none["box"] is None and none["volume_m3"] == 0.0


def test_intersection_and_volume_of_boxes():
    rw_c = workspace.intersect_boxes([[0, 2, 0, 2, 0, 2], [1, 3, -1, 1.5, 0.5, 4]])
    assert rw_c == pytest.approx([1, 2, 0, 1.5, 0.5, 2])
    assert workspace.box_volume(rw_c) == pytest.approx(1 * 1.5 * 1.5)
    assert workspace.box_volume([0, -1, 0, 1, 0, 1]) == 0.0


def _dphi_table():
    """A 3^3 grid of [0, 3]^3 m (1 m^3 voxels) with δφ = 1 mrad x (i + j + k) of the cell indices,
    ‖δp‖ = 1 m everywhere, the cell (1, 0, 0) not ok and the cell (0, 1, 0) ok without a δφ (NaN)."""
    n, box = 3, [0, 3, 0, 3, 0, 3]
    P = workspace.grid_points(box, n)
    idx = np.floor(P).astype(int)
    dphi = 1e-3 * idx.sum(axis=1)
    status = np.where((idx == [1, 0, 0]).all(axis=1), "slack", "ok")
    dphi[(idx == [0, 1, 0]).all(axis=1)] = np.nan
    df = pd.DataFrame({"x": P[:, 0], "y": P[:, 1], "z": P[:, 2], "dp": 1.0, "dphi": dphi, "status": status})
    return df, n, box


def test_error_limited_volume_on_dphi_counts_the_cells_under_the_limit():
    """Hand count: the cells with i + j + k <= 2 are 1 + 3 + 6 = 10; one is not ok and one has no δφ:
    8 voxels of 1 m^3, every one touching an uncounted voxel or the grid's edge (V_L_err = 4 m^3)."""
    df, n, box = _dphi_table()
    v = workspace.error_limited_volume(df, n, box, 0.002, envelope_volume=27.0, column="dphi")
    assert v["V_L"] == pytest.approx(8.0) and v["R_V"] == pytest.approx(8.0 / 27.0)
    assert v["V_L_err"] == pytest.approx(4.0)
    # the limit bounds δφ, not ‖δp‖ (1 m everywhere: nothing under 2 mm; everything ok under 1 m)
    assert workspace.error_limited_volume(df, n, box, 0.002, 27.0)["V_L"] == 0.0
    assert workspace.error_limited_volume(df, n, box, 1.0, 27.0)["V_L"] == pytest.approx(26.0)
    # the same values as ‖δp‖ give the same volume: the count does not depend on the column
    as_dp = df.assign(dp=df.dphi)
    assert workspace.error_limited_volume(as_dp, n, box, 0.002, 27.0) == v
    # every ok cell with a δφ is under the largest sum (6 mrad): 27 - 1 not ok - 1 NaN
    assert workspace.error_limited_volume(df, n, box, 0.006, 27.0, column="dphi")["V_L"] == pytest.approx(
        25.0
    )


def test_error_limited_volume_refuses_a_missing_or_unknown_column():
    df, n, box = _dphi_table()
    with pytest.raises(CdprError, match="no 'dphi' column"):
        workspace.error_limited_volume(df.drop(columns="dphi"), n, box, 0.01, 27.0, column="dphi")
    with pytest.raises(CdprError, match="column must be one of dp, dphi"):
        workspace.error_limited_volume(df, n, box, 0.01, 27.0, column="tension")


def test_read_box_round_trip_and_one_line_errors(tmp_path):
    good = tmp_path / "rw_c.json"
    good.write_text('{"box": [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]}', encoding="utf-8")
    assert workspace.read_box(good) == [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]
    with pytest.raises(CdprError, match="missing.json.*does not exist"):
        workspace.read_box(tmp_path / "missing.json")
    bad = tmp_path / "bad.json"
    for text in ('{"box": [1, 2, 3]}', '{"corners": []}', "not json"):
        bad.write_text(text, encoding="utf-8")
        with pytest.raises(CdprError, match="bad.json.*box"):
            workspace.read_box(bad)
    flat = tmp_path / "flat.json"
    flat.write_text('{"box": [0, 1, 0, 1, 2, 2]}', encoding="utf-8")  # zmin = zmax
    with pytest.raises(CdprError, match="ZMIN < ZMAX"):
        workspace.read_box(flat)


def test_solver_commands_do_not_load_the_sobol_or_plotting_libraries():
    """What a ``cdpr grid --box-file`` job and every job that reads a study import (start-up, issue
    16/19): not SALib and scipy.stats (0.4 s, the Sobol analysis and the truncated normal import
    them), not scipy.spatial (0.2 s, the envelope volume and the physical mode's hull import it)."""
    import subprocess
    import sys

    from tests.conftest import ROOT

    code = (
        "import sys; import cdpr.cli.commands, cdpr.analyses.workspace, cdpr.tables, cdpr.pipeline.study;"
        "print(*[m for m in ('SALib', 'scipy.stats', 'scipy.spatial', 'matplotlib') if m in sys.modules])"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True)
    assert out.stdout.strip() == "", f"loaded at start-up: {out.stdout.strip()}"
