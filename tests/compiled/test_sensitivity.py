"""The compiled sensitivities (cdpr.compiled.sensitivity) equal the numpy reference
(cdpr.models.sensitivity) with commanded lengths that differ from L_TS, on a grid with slack,
over-tension and inaccessible points; every subset's sensitivities and the linearised |dp| too."""

import numpy as np
import pytest

from cdpr.analyses.workspace import grid_points
from cdpr.compiled.sensitivity import linear_dp
from cdpr.models.inverse import L_TS
from cdpr.robot import load_robot, with_pulleys
from cdpr.solve import sensitivities, subset_sensitivities
from tests.conftest import ROBOTS

#: beyond the frame (anchors at +-2.5 m): slack (paper) and inaccessible (physical) points
BOX = [-3.1, 3.1, -3.1, 3.1, -0.2, 5.3]


def _robot(kind):
    """CDPR4 with a 600 kg platform: over-tension near the frame's edges and top."""
    return with_pulleys(load_robot(ROBOTS / "cdpr4.yaml", mass=600.0), kind=kind)


def _commanded(robot, P, seed=0):
    rng = np.random.default_rng(seed)
    return L_TS(robot, P) + rng.uniform(-0.005, 0.02, (len(P), robot.m))


@pytest.mark.parametrize("mode", ["paper", "physical"])
@pytest.mark.parametrize("kind", ["SR", "DR", "fixed"])
def test_compiled_equals_numpy_reference_with_commanded_lengths(kind, mode):
    robot = _robot(kind)
    P = grid_points(BOX, 8)
    L = _commanded(robot, P)
    a = sensitivities(robot, P, redundancy=mode, L=L, engine="numpy")
    b = sensitivities(robot, P, redundancy=mode, L=L)
    expected = {"ok", "over_tension", "slack" if mode == "paper" else "inaccessible"}
    assert expected <= set(a["status"])
    assert (a["status"] == b["status"]).all() and (a["smooth"] == b["smooth"]).all()
    assert np.array_equal(np.isnan(a["S"]), np.isnan(b["S"]))
    sm = a["smooth"]
    assert sm.sum() > 50
    scale = np.nanmax(np.abs(a["S"][sm]), axis=0)
    assert (np.abs(a["S"][sm] - b["S"][sm]) <= 1e-9 * scale).all()
    np.testing.assert_allclose(b["margin_t"][sm], a["margin_t"][sm], rtol=1e-8, atol=1e-6)
    np.testing.assert_allclose(b["cond"][sm], a["cond"][sm], rtol=1e-8)
    if mode == "paper":
        np.testing.assert_allclose(b["dp_gap"][sm], a["dp_gap"][sm], rtol=0, atol=1e-9)


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_subset_sensitivities_equal_numpy_reference(kind):
    robot = _robot(kind)
    P = grid_points(BOX, 6)
    L = _commanded(robot, P, seed=1)
    cols = [0, robot.m + 1, 2 * robot.m + 2, 3 * robot.m, 4 * robot.m + 4, 7 * robot.m]
    a = subset_sensitivities(robot, P, L=L, columns=cols, engine="numpy")
    b = subset_sensitivities(robot, P, L=L, columns=cols)
    np.testing.assert_array_equal(a["converged"], b["converged"])
    np.testing.assert_array_equal(a["admissible"], b["admissible"])
    c = a["converged"]
    assert c.any() and (~a["admissible"] & c).any()  # over-tension or slack subsets are there
    np.testing.assert_allclose(b["P"][c], a["P"][c], rtol=0, atol=1e-9)
    np.testing.assert_allclose(b["t"][c], a["t"][c], rtol=1e-9, atol=1e-6)
    for key in ("S", "St"):
        scale = np.nanmax(np.abs(a[key][c]), axis=(0, 1))
        assert (np.abs(a[key][c] - b[key][c]) <= 1e-8 * scale + 1e-12).all(), key
        assert np.array_equal(np.isnan(a[key]), np.isnan(b[key])), key


def test_linear_dp_equals_its_definition(cdpr4):
    """linear_dp = min over the valid slots whose linearised tensions lie in [0, T_a] of
    |dp0 + S delta| (numpy, vectorised); NaN where none."""
    robot = with_pulleys(cdpr4, kind="SR")
    P = grid_points(BOX, 5)
    ss = subset_sensitivities(robot, P)
    dp0, S, valid = ss["P"] - P[:, None, :], ss["S"], ss["converged"]
    rng = np.random.default_rng(2)
    delta = rng.normal(0.0, 3e-3, (6, S.shape[3])) / np.maximum(np.nanmax(np.abs(S), axis=(0, 1, 2)), 1e-12)
    for with_t in (False, True):
        got = linear_dp(dp0, S, valid, delta, *((ss["t"], ss["St"], ss["T_a"]) if with_t else ()))
        v = dp0[None] + np.einsum("ncak,sk->snca", np.nan_to_num(S), delta)
        adm = valid[None]
        if with_t:
            t = ss["t"][None] + np.einsum("ncak,sk->snca", np.nan_to_num(ss["St"]), delta)
            adm = adm & (t >= 0).all(axis=3) & (t <= ss["T_a"]).all(axis=3)
        norm = np.where(adm, np.linalg.norm(np.nan_to_num(v), axis=3), np.inf).min(axis=2)
        want = np.where(np.isfinite(norm), norm, np.nan)
        assert np.isfinite(want).any() and (np.isnan(want).any() or not with_t)  # slack points: no slot
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-15, equal_nan=True)
