"""The error budget's sag effect (issue 38): a design whose cables have a linear density > 0 gets the
fourth effect ``sag``; a massless design keeps today's three, its entries and columns unchanged.
What sag adds under the massless compensated lengths (``neglected_sag``) is > 0, and compensating
with the heavy model (``compensated_all``) leaves the heavy inverse's round trip (<= 1e-9 m)."""

import dataclasses

import numpy as np
import pytest

from cdpr.analyses import budget
from cdpr.robot import TABLE1, load_robot, with_pulleys, with_values
from tests.conftest import ROBOTS

#: CoGiRo's 4 mm steel cable (config/robots/cogiro.yaml).
RHO = 0.0631
#: The columns of a massless budget's summary, as before the sag effect.
POINT_COLUMNS = ["entry", "mean_m", "max_m", "share_m", "largest_fraction", "points", "ok_points"]


@pytest.fixture(scope="module")
def heavy4(cdpr4):
    """CDPR4's SR design (point mass) with a 4 mm steel cable of 0.0631 kg/m."""
    r = with_values(with_pulleys(cdpr4, kind="SR", h=0.1, r_p=0.0665), linear_density=RHO)
    assert r.heavy
    return r


@pytest.fixture(scope="module")
def points4():
    rng = np.random.default_rng(38)
    return np.column_stack([rng.uniform(-1.5, 1.5, 6), rng.uniform(-1.5, 1.5, 6), rng.uniform(0.5, 3.2, 6)])


@pytest.fixture(scope="module")
def heavy_budget(heavy4, points4):
    return budget.error_budget(heavy4, points4)


def test_massless_design_has_three_effects_and_the_same_columns(cdpr4):
    design = with_pulleys(cdpr4, kind="SR", h=0.1, r_p=0.0665)
    assert budget.effects_of(design) == budget.EFFECTS
    res = budget.error_budget(design, np.array([[0.3, -0.2, 1.5], [-0.5, 0.4, 2.5]]))
    assert list(res) == [*budget.variants(), "interaction"]
    assert not any("sag" in k for k in res)
    assert list(budget.summarise(res).columns) == POINT_COLUMNS


def test_the_entries_without_sag_are_those_of_the_massless_design(heavy4, heavy_budget, points4):
    """Every variant whose actual robot and model lack sag is the massless design's, to the bit."""
    light = budget.error_budget(with_values(heavy4, linear_density=0.0), points4)
    assert budget.effects_of(heavy4) == (*budget.EFFECTS, "sag")
    for name, (actual, model) in budget.variants(budget.effects_of(heavy4)).items():
        if "sag" not in actual and "sag" not in model:
            np.testing.assert_array_equal(heavy_budget[name]["dp"], light[name]["dp"], err_msg=name)
        else:
            assert name not in light or name == "all" or name.startswith(("compensated_", "neglected_"))


def test_sag_adds_an_error_and_the_heavy_compensation_removes_it(heavy_budget):
    ok = {k: r["status"] == "ok" for k, r in heavy_budget.items()}
    assert all(v.all() for v in ok.values())
    added = np.linalg.norm(heavy_budget["neglected_sag"]["dp"], axis=1)
    alone = np.linalg.norm(heavy_budget["sag"]["dp"], axis=1)
    # 5 m spans of a 4 mm steel cable: some 25-55 um under the massless compensated lengths, a few
    # um alone (fixed exit points, rigid cables commanded with L_TS: the platform sinks until the arcs fit)
    assert (added > 1e-5).all() and (added < 1e-3).all() and (alone > 5e-7).all() and (alone < added).all()
    assert np.linalg.norm(heavy_budget["compensated_all"]["dp"], axis=1).max() <= 1e-9


def test_four_effects_add_up(heavy_budget):
    s = sum(heavy_budget[k]["dp"] for k in (*budget.EFFECTS, "sag"))
    np.testing.assert_allclose(heavy_budget["interaction"]["dp"], heavy_budget["all"]["dp"] - s, atol=0)
    t = budget.summarise(heavy_budget).set_index("entry")
    total = t.loc[[*budget.EFFECTS, "sag", "interaction"], "share_m"].sum()
    assert total == pytest.approx(t.loc["all", "mean_m"], rel=1e-12)
    assert t.loc[[*budget.EFFECTS, "sag"], "largest_fraction"].sum() == pytest.approx(1.0)
    assert list(t.columns)[-1] == "p95_m"
    assert (t.mean_m <= t.max_m).all() and (t.p95_m <= t.max_m).all()
    text = budget.sentence("CDPR4_SR", t.reset_index())
    assert "cable sag adds" in text and "compensating with the heavy model leaves 0 mm" in text


def test_rigid_platform_sag_row(cogiro):
    """CoGiRo (8 cables, 6-DoF) with its 4 mm cable: what sag adds in position and orientation,
    and the heavy compensation's residual <= 1e-9 m, 1e-9 rad."""
    # the cogiro study's drum (config/studies/cogiro.yaml, budget.drum): Table 1 with l_u0 = 12 m
    design = budget.with_drums(
        with_values(cogiro, linear_density=RHO), dataclasses.replace(TABLE1, l_u0=12.0)
    )
    p = np.array([[0.0, 0.0, 1.5], [1.0, 1.0, 1.5], [-2.0, 1.0, 2.5]])
    names = ["none", "pulley", "sag", "all", "neglected_sag", "compensated_all"]
    res = {
        k: budget.variant(design, p, *budget.variants(budget.effects_of(design))[k], rotvec=[0.0, 0.0, 0.0])
        for k in names
    }
    assert all((r["status"] == "ok").all() for r in res.values())
    added = np.linalg.norm(res["neglected_sag"]["dp"], axis=1)
    assert (added > 2e-5).all() and (added < 2e-3).all()  # 0.1-0.3 mm (docs/heavy_cables.md)
    assert (np.linalg.norm(res["neglected_sag"]["dphi"], axis=1) > 1e-6).all()
    assert np.linalg.norm(res["compensated_all"]["dp"], axis=1).max() <= 1e-9
    assert np.linalg.norm(res["compensated_all"]["dphi"], axis=1).max() <= 1e-9
    light = budget.variant(
        with_values(cogiro, linear_density=0.0), p, ("pulley",), (), rotvec=[0.0, 0.0, 0.0]
    )
    np.testing.assert_array_equal(res["pulley"]["dp"], light["dp"])


@pytest.fixture(scope="module")
def cogiro():
    return load_robot(ROBOTS / "cogiro.yaml", linear_density=0.0)


def test_heavy_variants_take_the_compiled_kernel_where_it_models_the_pulleys(heavy4, heavy_budget, points4):
    """SR and DR designs are solved by the compiled kernel by default (it models every pulley):
    the default is the compiled engine's answer to the bit, and agrees with the numpy reference to
    1e-9 m (same statuses)."""
    dr = with_values(with_pulleys(heavy4, kind="DR", h=0.1, r_p=0.0665), linear_density=RHO)
    for design in (heavy4, dr):
        ref = budget.variant(design, points4, budget.effects_of(design), (), engine="numpy")
        got = budget.variant(design, points4, budget.effects_of(design), ())
        asked = budget.variant(design, points4, budget.effects_of(design), (), engine="compiled")
        np.testing.assert_array_equal(got["dp"], asked["dp"])
        np.testing.assert_array_equal(got["status"], ref["status"])
        np.testing.assert_allclose(got["dp"], ref["dp"], rtol=0, atol=1e-9)
