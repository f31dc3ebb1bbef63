"""The heavy inverse of one span (``cables.span_for_tension``) and of every cable at a pose
(``cables.HeavyCables.inverse``, issue 38): the span solved forward from the length found carries
the tension asked for at B (random spans, U-shaped, exit points below the attachment, EA = inf),
w = 0 is Hooke's spring in closed form, and the exit points and rest lengths of the inverse give back
the same exit points and tensions through the direct cable model (fixed and SR pulleys)."""

import numpy as np
import pytest

from cdpr.models import catenary as cat
from cdpr.models.cables import HeavyCables, span_for_tension
from cdpr.models.platform import pose_arrays
from cdpr.robot import load_robot, with_pulleys

W = 0.0631 * 9.81
EA = 102.2e9 * np.pi * 0.004**2 / 4


def test_span_for_tension_round_trip():
    rng = np.random.default_rng(3)
    n = 2000
    l_h = rng.uniform(0.05, 30.0, n)
    l_v = rng.uniform(-15.0, 25.0, n)
    # from the weight of a chord's length of cable (U-shaped spans) to 200 times it
    T = W * np.hypot(l_h, l_v) * rng.uniform(1.0, 200.0, n)
    H, V, L0, ok, it = span_for_tension(l_h, l_v, T, W, EA)
    assert ok.all() and it.max() <= 30
    s = cat.span_state(l_h, l_v, L0, W, EA)
    np.testing.assert_allclose(s.T_B, T, rtol=1e-8)
    np.testing.assert_allclose(s.H, H, rtol=1e-7, atol=1e-9 * T.max())
    assert (s.status == "U").any() and (s.status == "catenary").any()


def test_span_for_tension_inextensible_and_weightless():
    l_h, l_v, T = np.array([4.0, 10.0]), np.array([3.0, -2.0]), np.array([200.0, 900.0])
    H, V, L0, ok, _ = span_for_tension(l_h, l_v, T, W, np.inf)
    assert ok.all()
    np.testing.assert_allclose(cat.span_state(l_h, l_v, L0, W, np.inf).T_B, T, rtol=1e-7)
    H, V, L0, ok, it = span_for_tension(l_h, l_v, T, 0.0, EA)
    assert ok.all() and (it == 0).all()
    c = np.hypot(l_h, l_v)
    np.testing.assert_allclose(L0, c / (1.0 + T / EA), rtol=1e-15)
    np.testing.assert_allclose(H, T * l_h / c, rtol=1e-14)


def test_span_for_tension_flags_what_it_cannot_solve():
    # no tension, and a cable hanging 10 m down from B with less tension at B than 10 m of its weight
    _, _, L0, ok, _ = span_for_tension([3.0, 3.0, 0.5], [1.0, 1.0, -10.0], [0.0, -5.0, 5.0 * W], W, EA)
    assert not ok.any() and np.isnan(L0).all()


@pytest.mark.parametrize("kind", ["fixed", "SR"])
def test_cable_inverse_gives_back_its_exit_points_and_tensions(kind):
    r = with_pulleys(load_robot("config/robots/cdpr4.yaml", linear_density=0.0631), kind=kind)
    p, R = pose_arrays(np.array([[0.3, -0.5, 2.0], [1.5, 1.2, 3.5]]))
    t = np.array([[900.0, 1200.0, 700.0, 300.0], [50.0, 2000.0, 3000.0, 1000.0]])
    cab = HeavyCables(r)
    inv = cab.inverse(p, R, t)
    assert inv["converged"].all()
    x = cab.exit_points(p, R, inv["L0"])
    assert np.abs(x["D"] - inv["D"]).max() <= 1e-12
    np.testing.assert_allclose(x["state"].span.T_B, t, rtol=1e-8)
    np.testing.assert_allclose(np.linalg.norm(inv["f"], axis=-1), 1.0, rtol=1e-14)
