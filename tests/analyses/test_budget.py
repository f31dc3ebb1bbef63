"""Error budget (cdpr.analyses.budget): the limits (no effect -> no error, everything compensated -> no
error, E -> infinity), the additive split, the winch's length error through the drum."""

import dataclasses

import numpy as np
import pytest

from cdpr.analyses import budget
from cdpr.analyses.workspace import grid_points
from cdpr.models import winch
from cdpr.models.inverse import L_TS
from cdpr.robot import TABLE1, with_pulleys

RW_C = [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]


@pytest.fixture(scope="module")
def points():
    return grid_points(RW_C, 5)


@pytest.fixture(scope="module", params=["SR", "DR"])
def design(request, cdpr4):
    return with_pulleys(cdpr4, kind=request.param, h=0.1, r_p=0.0665)


@pytest.fixture(scope="module")
def result(design, points):
    return budget.error_budget(design, points)


def test_all_effects_off_gives_no_error(result):
    r = result["none"]
    assert (r["status"] == "ok").all()
    # fixed exit points, rigid cables (E x 1e6: the stretch left is ~1e-8 m), an exact drum
    assert np.linalg.norm(r["dp"], axis=1).max() < 1e-7


def test_compensating_every_effect_gives_no_error(result):
    r = result["compensated_all"]
    assert (r["status"] == "ok").all() and np.linalg.norm(r["dp"], axis=1).max() < 1e-9


def test_each_effect_alone_is_nonzero_and_of_its_size(result):
    n = {k: np.linalg.norm(result[k]["dp"], axis=1) for k in budget.EFFECTS}
    assert 0.01 < n["pulley"].mean() < 0.3  # cm to dm (Paty 2021 Fig. 12)
    assert 1e-3 < n["elasticity"].mean() < 0.05  # mm to cm of elastic sag
    assert 1e-4 < n["winch"].mean() < 3e-3  # the drum's |dl| <= 1.5 mm (Metillon 2022 Fig. 7b)


def test_interaction_is_what_the_single_effects_do_not_add_up_to(result):
    s = sum(result[k]["dp"] for k in budget.EFFECTS)
    np.testing.assert_allclose(result["interaction"]["dp"], result["all"]["dp"] - s, atol=0)


def test_shares_add_up_to_the_all_effects_error(result):
    t = budget.summarise(result).set_index("entry")
    total = t.loc[[*budget.EFFECTS, "interaction"], "share_m"].sum()
    assert total == pytest.approx(t.loc["all", "mean_m"], rel=1e-12)
    assert t.loc[list(budget.EFFECTS), "largest_fraction"].sum() == pytest.approx(1.0)
    assert budget.dominant(t.reset_index()) == "pulley"


def test_rigid_limit_has_converged(design, points):
    """E x RIGID stands for E -> infinity: ten times stiffer moves the pulley-only pose by < 1 um."""
    a = budget.variant(design, points, ("pulley",), ())
    old = budget.RIGID
    try:
        budget.RIGID = old * 10
        b = budget.variant(design, points, ("pulley",), ())
    finally:
        budget.RIGID = old
    ok = (a["status"] == "ok") & (b["status"] == "ok")
    assert ok.mean() > 0.9 and np.abs(a["dp"][ok] - b["dp"][ok]).max() < 1e-6


def test_the_drum_adds_its_length_error(cdpr4, points):
    """Commanding the no-winch angle q_nw to a drum whose exit point moves pays out L0 + dl
    (to first order in the exit point's motion); a model that knows the winch pays out L0."""
    fixed = with_pulleys(cdpr4, kind="fixed")
    L = L_TS(fixed, points)
    got = budget.realised_lengths(fixed, L, ("winch",), ())
    dl = np.column_stack([winch.length_error(TABLE1, L[:, i] - fixed.d[i]) for i in range(4)])
    np.testing.assert_allclose(got - L, dl, atol=2e-5)
    np.testing.assert_array_equal(budget.realised_lengths(fixed, L, ("winch",), ("winch",)), L)
    # a model that knows the winch, on a drum whose exit point does not move: off by -dl
    back = budget.realised_lengths(fixed, L, (), ("winch",))
    np.testing.assert_allclose(back - L, -dl, atol=2e-5)


def test_the_design_own_winch_is_kept_and_unknown_effects_refused(cdpr4):
    w = dataclasses.replace(TABLE1, k_w=0.08)
    robot = dataclasses.replace(cdpr4, cables=tuple(dataclasses.replace(c, winch=w) for c in cdpr4.cables))
    assert budget.effect_robot(robot, ()).winches == (w,) * 4
    assert budget.effect_robot(cdpr4, ()).winches == (TABLE1,) * 4
    with pytest.raises(ValueError, match="unknown effect"):
        budget.effect_robot(cdpr4, ("gravity",))


def test_sentence_names_the_dominant_effect(result):
    t = budget.summarise(result)
    s = budget.sentence("CDPR4_X", t, t)
    assert s.startswith("CDPR4_X: pulley geometry dominates over RW_C") and s.endswith(".")
