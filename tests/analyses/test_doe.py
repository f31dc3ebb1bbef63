"""cdpr.analyses.doe: global index (eq. 15), 2^3 factorial, effects, valley and optimal line."""

import numpy as np
import pytest

from cdpr.analyses import doe


def test_full_factorial_is_table_2_order():
    X = doe.full_factorial(3)
    assert X.shape == (8, 3)
    assert X[:, 0].tolist() == [-1, -1, -1, -1, 1, 1, 1, 1]  # joint slowest, as in Table 2
    assert X[:, 2].tolist() == [-1, 1] * 4


def test_effects_of_a_known_response():
    """y = 10 + 2 j - 3 h + 0.5 r + 1.5 j h + 0.25 j h r: coded coefficients are the half-effects."""
    X = doe.full_factorial(3)
    j, h, r = X.T
    y = 10 + 2 * j - 3 * h + 0.5 * r + 1.5 * j * h + 0.25 * j * h * r
    e = doe.effects(X, y, ["joint", "h", "r_p"]).set_index("term")
    expect = {
        "mean": 10,
        "joint": 2,
        "h": -3,
        "r_p": 0.5,
        "joint:h": 1.5,
        "joint:r_p": 0,
        "h:r_p": 0,
        "joint:h:r_p": 0.25,
    }
    for term, c in expect.items():
        assert e.coefficient[term] == pytest.approx(c, abs=1e-12)
        assert e.ols_coefficient[term] == pytest.approx(c, abs=1e-12)  # OLS on the saturated model agrees
        assert e.effect[term] == pytest.approx(c if term == "mean" else 2 * c, abs=1e-12)
    assert [e.abs_effect_rank[t] for t in ("mean", "h", "joint")] == [1, 2, 3]  # the rank counts the mean too


def test_global_index_is_the_mean_over_ok_points():
    dp = np.array([0.1, 0.2, 0.3, 9.0])
    st = np.array(["ok", "ok", "ok", "slack"])
    ix, bad = doe.global_index(dp, st)
    assert ix == pytest.approx(0.2) and bad == 1
    ix, bad = doe.global_index(dp, np.array(["slack"] * 4))
    assert np.isnan(ix) and bad == 4


def test_valley_refines_a_parabola_and_the_line_through_the_origin():
    r_p = np.tile(np.linspace(0.01, 0.1, 10), 3)
    h = np.repeat([0.05, 0.1, 0.15], 10)
    k_true = 1.7
    index = (r_p - h / k_true) ** 2 + 0.01
    v = doe.valley(r_p, h, index)
    assert v.refined.all()
    np.testing.assert_allclose(v.r_p_star, v.h / k_true, atol=1e-12)  # exact for a parabola
    assert doe.line_through_origin(v.r_p_star, v.h) == pytest.approx(k_true)
    assert doe.line_field_point(2.0, (0.035, 0.098), (0.1, 0.15)) == pytest.approx((0.05, 0.1))
    assert doe.line_field_point(10.0, (0.035, 0.098), (0.1, 0.15)) is None
