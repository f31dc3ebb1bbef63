"""The global-index jobs of the DOE and of the E sweep (``tasks.index_shard``, ``tasks.elasticity_shard``):
one process per slice of the tests or moduli, one solve per orbit of the grid's symmetries."""

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from cdpr.analyses import doe
from cdpr.analyses.workspace import grid_points
from cdpr.errors import CdprError
from cdpr.pipeline import study, tasks
from cdpr.solve import solve_points_any

ROOT = Path(__file__).resolve().parents[2]
BOX = [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]


@pytest.fixture()
def quick(monkeypatch, tmp_path):
    monkeypatch.chdir(ROOT)
    st = study.load_study(ROOT / "config" / "studies" / "quick_physical.yaml")
    box = tmp_path / "rw_c.json"
    box.write_text(json.dumps({"box": BOX}))
    return st, box


def _full_grid_index(st, robot, n):
    """eq. 15 over every point of the n^3 grid, each solved (no symmetry)."""
    res = solve_points_any(robot, grid_points(BOX, n), method=st["solver"], redundancy=study.redundancy(st))
    return doe.global_index(res["dp"], np.asarray(res["status"]).astype(str))


def test_the_doe_shards_share_the_tests_and_give_the_full_grids_index(quick, tmp_path):
    st, box = quick
    shards = [tmp_path / f"tests_{k}.parquet" for k in range(st["doe"]["shards"])]
    for k, p in enumerate(shards):
        tasks.index_shard(st, str(k), str(box), str(p))
    rows = pd.concat([pd.read_parquet(p) for p in shards], ignore_index=True)
    assert list(rows.test) == list(range(1, 9))  # every test once, in order, over 2 shards
    assert len(pd.read_parquet(shards[0])) == 4
    tests = study.doe_tests(st)
    for t in (1, 8):  # SR and DR, both levels of h and r_p
        spec = tests.set_index("test").loc[t, ["kind", "h_m", "r_p_m"]].to_dict()
        robot = study.design_robot(st, st["doe"]["robot"], spec)
        ix, bad = _full_grid_index(st, robot, st["doe"]["index_n"])
        row = rows[rows.test == t].iloc[0]
        assert row.not_ok_points == bad
        assert row.index_m == pytest.approx(ix, rel=1e-9)  # solver tolerance, not the same solves
    assert "index_phi_rad" not in rows  # a point mass has no orientation


def test_the_elasticity_shards_share_the_moduli_of_each_design(quick, tmp_path):
    st, box = quick
    moduli = study.E_values(st)
    paths = [tmp_path / f"SRopt_{k}.parquet" for k in range(st["elasticity"]["shards"])]
    for k, p in enumerate(paths):
        tasks.elasticity_shard(st, "SRopt", str(k), str(box), str(p))
    rows = pd.concat([pd.read_parquet(p) for p in paths], ignore_index=True)
    assert list(rows.E_Pa) == moduli and set(rows.design) == {"SRopt"}
    robot = study.design_robot(st, st["doe"]["robot"], st["optimal"]["SRopt"], E=moduli[0])
    ix, bad = _full_grid_index(st, robot, st["elasticity"]["index_n"])
    assert rows.index_m.iloc[0] == pytest.approx(ix, rel=1e-9) and rows.not_ok_points.iloc[0] == bad
    assert rows.index_m.nunique() == len(moduli)  # each modulus its own solve


def test_a_missing_doe_test_is_named(quick, tmp_path):
    st, box = quick
    p = tmp_path / "tests_0.parquet"
    tasks.index_shard(st, "0", str(box), str(p))
    out = {k: str(tmp_path / f"o.{k}") for k in ("csv", "e.csv", "png", "f.png")}
    with pytest.raises(CdprError, match=r"no shard of DOE test\(s\) 5, 6, 7, 8"):
        tasks.doe_results(st, [str(p)], out["csv"], out["e.csv"], out["png"], out["f.png"])
