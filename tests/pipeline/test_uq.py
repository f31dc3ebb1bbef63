"""The uncertainty study's experiments (cdpr.pipeline.uq) on the quick study: Monte Carlo shards are
reproducible whatever the number of shards."""

import copy
import os

import pandas as pd
import pytest

from cdpr.pipeline import uq
from cdpr.pipeline.study import Study, load_study
from tests.conftest import ROOT

QUICK = ROOT / "config" / "studies" / "quick.yaml"
RW_C = [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]


@pytest.fixture(scope="module")
def quick():
    cwd = os.getcwd()
    os.chdir(ROOT)
    try:
        yield load_study(QUICK)
    finally:
        os.chdir(cwd)


def _study(st, **mc):
    s = Study(copy.deepcopy(dict(st)))
    s.path = st.path
    s["uncertainty"]["monte_carlo"].update(mc)
    return s


def test_monte_carlo_reproducible_across_shard_counts(quick):
    """The same seed gives the same per-sample numbers, full solves and linearised, on 1 or 3 shards."""
    one = uq.mc_shard(_study(quick, full_samples=6, shards=1), "DRopt", "uncompensated", RW_C, 0)[0]
    three = pd.concat(
        [
            uq.mc_shard(_study(quick, full_samples=6, shards=3), "DRopt", "uncompensated", RW_C, k)[0]
            for k in range(3)
        ],
        ignore_index=True,
    )
    pd.testing.assert_frame_equal(one, three)
    assert one["index_full_m"].nunique() == 6  # the samples differ from each other


def test_agreement_does_not_depend_on_the_shard_count(quick):
    """The agreement of the linearisation with the full solves, from 1 or 3 shards' tables (each
    shard's point table repeats every point): the same numbers, and a point counts as disagreeing
    when any sample disagrees there (a tolerance that some but not all samples exceed)."""
    first = uq.mc_shard(_study(quick, full_samples=6, shards=1), "DRopt", "uncompensated", RW_C, 0)[1]
    tol = float(first["max_diff_m"].median())  # some points above it, some below
    runs = {}
    for shards in (1, 3):
        st = _study(quick, full_samples=6, shards=shards, agree_tol_m=tol)
        parts = [uq.mc_shard(st, "DRopt", "uncompensated", RW_C, k) for k in range(shards)]
        runs[shards] = [pd.concat([p[i] for p in parts], ignore_index=True) for i in (0, 1)]
    assert len(runs[3][1]) == 3 * len(runs[1][1])
    a1 = uq.agreement(*runs[1], tol)
    a3 = uq.agreement(*runs[3], tol)
    assert a1 == a3
    assert 0.0 < a1["share_points_disagree"] < 1.0
