"""The engine registry (cdpr.solve): every public entry point that takes ``engine`` refuses an unknown
one and a pair that does not exist with one CdprError naming the allowed values, and its default is
the same engine everywhere (compiled for Newton, numpy for the fixed point)."""

import numpy as np
import pytest

from cdpr import solve, tables
from cdpr.analyses import budget, compensation, uncertainty
from cdpr.errors import CdprError
from cdpr.parameters import parameter_values
from cdpr.robot import with_pulleys

PTS = np.array([[0.7, -1.3, 0.4], [-1.6, 0.5, 1.9], [1.1, 1.9, 3.1], [0.0, 0.0, 4.95]])
UNKNOWN = "unknown engine 'nope'; allowed: compiled, numpy"


@pytest.fixture(scope="module")
def robot(cdpr4):
    return with_pulleys(cdpr4, kind="SR", h=0.1077, r_p=0.035)


def _linear_inputs(seed=3, N=7, C=4, k=5, n=40):
    rng = np.random.default_rng(seed)
    dp0 = rng.normal(0, 1e-3, (N, C, 3))
    S = rng.normal(0, 1e-3, (N, C, 3, k))
    valid = rng.random((N, C)) > 0.2
    delta = rng.normal(0, 1, (n, k))
    t0 = rng.uniform(-100, 3000, (N, C, 3))
    St = rng.normal(0, 300, (N, C, 3, k))
    T_a = np.full((C, 3), 2500.0)
    return dp0, S, valid, delta, t0, St, T_a


def _entry_points(robot):
    """(name, call(engine)) for every public function or method that takes ``engine``."""
    lin = _linear_inputs()
    theta = parameter_values(robot) * np.r_[np.full(4, 0.9), np.ones(7 * 4 - 4 + 1)]
    return [
        ("solve", lambda e: solve.solve(robot, PTS, engine=e)),
        (
            "solve physical",
            lambda e: solve.solve(robot, PTS, engine=e, redundancy="physical"),
        ),
        ("solve_table", lambda e: tables.solve_table(robot, PTS, engine=e)),
        ("sensitivities", lambda e: solve.sensitivities(robot, PTS, engine=e)),
        ("subset_sensitivities", lambda e: solve.subset_sensitivities(robot, PTS, engine=e)),
        ("linear_dp", lambda e: solve.linear_dp(*lin, engine=e)),
        ("compensate", lambda e: compensation.compensate(robot, PTS, method="subset", engine=e)),
        ("compensated_pose", lambda e: compensation.compensated_pose(robot, PTS, engine=e)),
        ("budget.variant", lambda e: budget.variant(robot, PTS, ("elasticity",), (), engine=e)),
        ("PoseErrorModel", lambda e: uncertainty.PoseErrorModel(robot, PTS, engine=e).solve(theta)),
    ]


def test_check_engine_defaults_and_refusals():
    assert solve.check_engine(None, "newton") == "compiled"
    assert solve.check_engine(None, "fixed_point") == "numpy"
    for e, methods in solve.ENGINES.items():
        for m in methods:
            assert solve.check_engine(e, m) == e
    with pytest.raises(CdprError, match=UNKNOWN):
        solve.check_engine("nope", "newton")
    with pytest.raises(CdprError, match="compiled/newton, numpy/newton, numpy/fixed_point"):
        solve.check_engine("compiled", "fixed_point")


def test_a_one_shot_process_below_the_threshold_defaults_to_numpy():
    n = solve.ONE_SHOT_POSES
    assert solve.check_engine(None, "newton", one_shot=1) == "numpy"
    assert solve.check_engine(None, "newton", one_shot=n - 1) == "numpy"
    assert solve.check_engine(None, "newton", one_shot=n) == "compiled"
    assert solve.check_engine(None, "fixed_point", one_shot=n) == "numpy"
    assert solve.check_engine("compiled", "newton", one_shot=1) == "compiled"  # a named engine is kept
    with pytest.raises(CdprError, match=UNKNOWN):
        solve.check_engine("nope", "newton", one_shot=1)


def test_every_entry_point_refuses_an_unknown_engine(robot):
    calls = _entry_points(robot)
    assert len(calls) == 10
    for name, call in calls:
        with pytest.raises(CdprError, match=UNKNOWN):
            call("nope")
            pytest.fail(f"{name} accepted engine='nope'")


def test_a_pair_that_does_not_exist_is_refused(robot):
    for call in (solve.solve, tables.solve_table):
        with pytest.raises(CdprError, match="the compiled engine has no 'fixed_point' solver"):
            call(robot, PTS, method="fixed_point", engine="compiled")
    with pytest.raises(CdprError, match="physical mode has one solver"):
        solve.solve(robot, PTS, method="fixed_point", redundancy="physical")
    with pytest.raises(CdprError, match="unknown redundancy 'both'; allowed: paper, physical"):
        solve.sensitivities(robot, PTS, redundancy="both")


def _same(a, b, name):
    """Results of two calls: dicts of arrays, DataFrames or arrays, equal to the last bit."""
    if isinstance(a, dict):
        assert a.keys() == b.keys(), name
        for key in a:
            _same(a[key], b[key], f"{name}[{key}]")
    elif isinstance(a, tuple):
        for x, y in zip(a, b, strict=True):
            _same(x, y, name)
    elif hasattr(a, "equals"):
        assert a.equals(b), name
    else:
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b), err_msg=name)


def test_the_default_is_the_compiled_engine_everywhere(robot):
    """Newton: the default is compiled at every entry point (identical results), and the numpy
    reference is a different computation that agrees with it (so the comparison can fail)."""
    for name, call in _entry_points(robot):
        default, compiled = call(None), call("compiled")
        _same(default, compiled, name)
    res = {e: solve.solve(robot, PTS, engine=e) for e in ("compiled", "numpy")}
    np.testing.assert_array_equal(res["compiled"]["status"], res["numpy"]["status"])
    ok = res["numpy"]["status"] == "ok"
    assert ok.sum() >= 3
    assert np.abs(res["compiled"]["P_s"][ok] - res["numpy"]["P_s"][ok]).max() < 1e-9


def test_the_fixed_point_default_is_numpy(robot):
    a = tables.solve_table(robot, PTS, method="fixed_point")
    b = tables.solve_table(robot, PTS, method="fixed_point", engine="numpy")
    assert a.equals(b)


def test_linear_dp_engines_agree():
    """The compiled kernel and the numpy reference of the linearised ‖dp‖: the same minimum over the
    admissible slots, NaN where none is."""
    args = _linear_inputs()
    a = solve.linear_dp(*args, engine="numpy")
    b = solve.linear_dp(*args, engine="compiled")
    assert np.array_equal(np.isnan(a), np.isnan(b))
    assert np.isnan(a).any() and np.isfinite(a).sum() > 100
    fin = np.isfinite(a)
    np.testing.assert_allclose(a[fin], b[fin], rtol=1e-12, atol=0)
    # without tensions (physical mode): every valid slot counts
    c = solve.linear_dp(*args[:4], engine="numpy")
    d = solve.linear_dp(*args[:4])
    np.testing.assert_allclose(c, d, rtol=1e-12, atol=0)
    assert (np.nan_to_num(c, nan=np.inf) <= np.nan_to_num(a, nan=np.inf)).all()


@pytest.mark.parametrize("engine", ["numpy", "compiled"])
@pytest.mark.parametrize("redundancy", ["paper", "physical"])
def test_zero_points_give_empty_results_in_both_modes(robot, engine, redundancy):
    """Solving no point (a caller's selection of feasible points can be empty) returns empty arrays of
    the right shapes in both modes and engines, and so do the sensitivities: no error."""
    P = np.zeros((0, 3))
    res = solve.solve(robot, P, redundancy=redundancy, engine=engine)
    assert res["P_s"].shape == (0, 3) and res["dp"].shape == (0,) and len(res["status"]) == 0
    if redundancy == "physical":
        res = solve.solve(robot, P, redundancy=redundancy, engine=engine, L0=np.zeros((0, 4)))
        assert res["P_s"].shape == (0, 3) and res["t"].shape == (0, 4)
    sens = solve.sensitivities(robot, P, redundancy=redundancy, engine=engine)
    assert len(sens["status"]) == 0
