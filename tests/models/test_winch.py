"""Winch model (Metillon et al. 2022) against its Fig. 7 numbers and its own geometry."""

import math

import numpy as np
import pytest

from cdpr.errors import ConfigError
from cdpr.models import winch
from cdpr.robot import TABLE1, load_winch_params

P = TABLE1


def test_length_error_end_values_fig7b():
    dl = winch.length_error(P, np.array([0.0, 5.0]))
    assert dl[0] * 1e3 == pytest.approx(1.46, abs=0.01)  # "1.46 mm for l_pm = 0 m"
    assert dl[1] * 1e3 == pytest.approx(-0.82, abs=0.01)  # "-0.82 mm for l_pm = 5 m"


def test_physical_root_passes_through_initial_state():
    l0 = winch.l_pm0(P)
    q1, q2 = winch.roots(P, l0)
    assert q1 == pytest.approx(P.q0, abs=1e-9)
    assert abs(q2 - P.q0) > 1.0
    assert winch.length_error(P, l0) == pytest.approx(0.0, abs=1e-12)


def test_q1_solves_the_unsquared_equation_and_q2_does_not():
    l_pm = np.linspace(0, 5, 11)
    q1, q2 = winch.roots(P, l_pm)
    X = P.l_u0 + P.k_w * P.q0 - l_pm
    assert np.abs(winch.l_AE(P, q1) - (X - P.k_w * q1)).max() < 1e-10
    assert (np.abs(winch.l_AE(P, q2) - (X - P.k_w * q2)) > 1.0).all()
    assert (q1 < q2).all() and (np.diff(q1) < 0).all()


def test_leading_coefficient_is_minus_rw_squared():
    mu = 2 * math.pi * P.l_E1E2 / P.q_max
    r_w = math.sqrt(P.k_w**2 - (mu / (2 * math.pi)) ** 2)
    a, _, _ = winch.coefficients(P, 1.0)
    assert a == pytest.approx(-(r_w**2), rel=1e-12)  # corrected eq. (27)


def test_geometry_gives_consistent_parameters():
    r_w = winch.coiling_radius(0.08, 0.002, 0.004)
    mu = 0.002
    a = np.array([0.3, 0.0, 2.0])
    p = winch.params_from_geometry(np.eye(3), np.zeros(3), a, r_w, mu, 0.06, q0=10.0, l_u0=5.0)
    assert p.q_max == pytest.approx(2 * math.pi * 0.06 / mu)
    assert p.k_w == pytest.approx(math.hypot(r_w, mu / (2 * math.pi)))
    e1, e2 = winch.exit_points(np.eye(3), np.zeros(3), a, r_w, 0.06)
    assert np.linalg.norm(e1[[0, 2]]) == pytest.approx(r_w)  # on the drum
    assert np.dot(e1 - a, e1) == pytest.approx(0.0, abs=1e-12)  # AE1 tangent: D1E1 perpendicular to AE1
    assert np.linalg.norm(e2 - e1) == pytest.approx(0.06)
    # |e(q) - a| by the law of cosines equals the direct distance
    q = np.array([0.0, 30.0, p.q_max])
    direct = np.linalg.norm(winch.exit_point(e1, e2, q, p.q_max) - a, axis=1)
    assert np.allclose(winch.l_AE(p, q), direct)


def test_bad_params_file(tmp_path):
    f = tmp_path / "w.yaml"
    f.write_text("k_w_m: -1\n")
    with pytest.raises(ConfigError, match="w.yaml: key 'k_w_m': must be strictly positive"):
        load_winch_params(f)
    f.write_text("kw: 1\n")
    with pytest.raises(ConfigError, match="key 'kw': unknown key"):
        load_winch_params(f)
