"""Extended inverse model (eq. 3-7): limits, tangency, continuity under a pulley."""

import numpy as np
import pytest

from cdpr.models.inverse import L_TS, igm_e
from cdpr.robot import with_pulleys

rng = np.random.default_rng(12345)
PTS = np.column_stack([rng.uniform(-2.4, 2.4, 500), rng.uniform(-2.4, 2.4, 500), rng.uniform(0, 4.8, 500)])


@pytest.mark.parametrize("kind", ["fixed", "SR", "DR"])
def test_zero_pulley_gives_standard_model(cdpr4, kind):
    r = with_pulleys(cdpr4, kind=kind, h=0.0, r_p=0.0)
    assert np.abs(igm_e(r, PTS).L_TE - L_TS(r, PTS)).max() < 1e-12


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_tangency_and_sheave_radius(cdpr4, kind):
    r = with_pulleys(cdpr4, kind=kind)
    st = igm_e(r, PTS)
    C = r.A - np.array([0, 0, 1.0]) * r.d[:, None]
    d_vec, l_E = st.D - st.H, PTS[:, None, :] - st.D
    k_vec, l_d = st.K - st.H, st.K - C
    assert np.allclose(np.linalg.norm(d_vec, axis=-1), r.r_p)
    assert np.allclose(np.linalg.norm(k_vec, axis=-1), r.r_p)
    assert np.abs(np.einsum("...i,...i", d_vec, l_E)).max() < 1e-10  # l_E perpendicular to d
    assert np.abs(np.einsum("...i,...i", k_vec, l_d)).max() < 1e-10  # l_d perpendicular to k
    assert np.allclose(np.linalg.norm(l_E, axis=-1), st.l_E)
    assert np.allclose(np.linalg.norm(l_d, axis=-1), st.l_d)
    # wrap over the top: between 0 and pi + a bit in the workspace
    assert (st.gamma > 0).all() and (st.gamma < 1.5 * np.pi).all()
    # |H - A| = h
    assert np.allclose(np.linalg.norm(st.H - r.A, axis=-1), r.h)


def test_sr_dead_length_is_constant(cdpr4):
    st = igm_e(cdpr4, PTS)
    assert np.allclose(st.l_d, np.sqrt(4.0**2 + 0.1**2 - 0.0665**2))


def test_dr_arm_on_bisector(cdpr4):
    r = with_pulleys(cdpr4, kind="DR")
    st = igm_e(r, PTS)
    e_C = np.array([0, 0, -1.0])
    e_P = PTS[:, None, :] - r.A
    e_P /= np.linalg.norm(e_P, axis=-1, keepdims=True)
    arm = (st.H - r.A) / 0.1
    assert np.allclose(np.einsum("...i,...i", arm, e_C), np.einsum("...i,...i", arm, e_P))
    assert (arm[..., 2] < 0).all()  # the sheave hangs below its joint (erratum on a_i)


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_continuity_directly_under_a_pulley(cdpr4, kind):
    r = with_pulleys(cdpr4, kind=kind)
    A1 = r.A[0]
    on_axis = igm_e(r, np.array([[A1[0], A1[1], 2.0]]))
    assert np.isfinite(on_axis.L_TE).all() and np.isfinite(on_axis.D).all()
    for ang in np.linspace(0, 2 * np.pi, 7):
        for eps in (1e-3, 1e-6, 1e-9):
            P = np.array([[A1[0] + eps * np.cos(ang), A1[1] + eps * np.sin(ang), 2.0]])
            near = igm_e(r, P)
            assert abs(near.L_TE[0, 0] - on_axis.L_TE[0, 0]) < 10 * eps
            assert abs(near.gamma[0, 0] - on_axis.gamma[0, 0]) < 10 * eps / 0.0665 + 1e-12
