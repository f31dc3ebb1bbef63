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
