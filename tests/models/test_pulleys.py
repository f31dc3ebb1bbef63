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


# ---------------------------------------------------------------------------------------------
# Pulleys at any orientation (issue 17)
# ---------------------------------------------------------------------------------------------
from cdpr.models.pulleys import (  # noqa: E402
    pulley_state,
    swivel,
    total_length_and_direction,
    wrap_over_270,
)
from cdpr.models.statics import length_gradient  # noqa: E402
from cdpr.robot import KIND_CODE, pulley_frame  # noqa: E402


def random_pulleys(kind, m=6, seed=7):
    """m pulleys at random axes and anchors, each with a random attachment point B_i in front of it
    (on the +k side, away from the sheave)."""
    g = np.random.default_rng(seed)
    axis = g.normal(size=(m, 3))
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    frame = np.array([pulley_frame(a) for a in axis])
    A = g.uniform(-3, 3, size=(m, 3))
    h, r_p = (0.0, 0.0) if kind == "fixed" else ((0.1, 0.0665) if kind == "SR" else (0.15, 0.05))
    args = (A, np.full(m, KIND_CODE[kind], dtype=np.int8), np.full(m, h), np.full(m, r_p), np.full(m, 2.0))
    inward = np.tile([1.0, 0.0], (m, 1))
    # B_i = A_i + 1.5 k_i + 1.2 (random direction perpendicular to k_i): below the sheave, seen from k_i
    e = g.normal(size=(20, m, 3))
    e -= np.einsum("nma,ma->nm", e, axis)[..., None] * axis
    e /= np.linalg.norm(e, axis=-1, keepdims=True)
    B = A + g.uniform(0.5, 2.0, size=(20, m, 1)) * e - g.uniform(0.5, 2.0, size=(20, m, 1)) * axis
    return args, inward, frame, B


@pytest.mark.parametrize("kind", ["fixed", "SR", "DR"])
def test_length_gradient_is_minus_u_at_random_axes(kind):
    """dL_TE/dB_i = -u_i (fixed, SR; DR: -u plus the arm term of length_gradient), central differences."""
    args, inward, frame, B = random_pulleys(kind)
    g = total_length_and_direction(B, *args, inward, frame, per_cable=True)
    h = 1e-6
    fd = np.empty(B.shape)
    for a in range(3):
        dB = np.zeros(3)
        dB[a] = h
        Lp = pulley_state(B + dB, *args, inward, frame, per_cable=True).L_TE
        Lm = pulley_state(B - dB, *args, inward, frame, per_cable=True).L_TE
        fd[..., a] = (Lp - Lm) / (2 * h)
    assert np.abs(fd - length_gradient(g)).max() < 1e-8
    if kind != "DR":
        assert np.abs(fd + g.u).max() < 1e-8


def test_zero_pulley_is_the_straight_line_at_any_axis():
    args, inward, frame, B = random_pulleys("SR")
    A, kind, _, _, d = args
    st = pulley_state(B, A, kind, np.zeros(6), np.zeros(6), d, inward, frame, per_cable=True)
    assert np.abs(st.L_TE - (np.linalg.norm(B - A, axis=-1) + d)).max() < 1e-12


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_rotating_the_whole_robot_rotates_the_answers(kind):
    from scipy.spatial.transform import Rotation

    args, inward, frame, B = random_pulleys(kind)
    A = args[0]
    Q = Rotation.from_rotvec([0.3, -1.1, 0.7]).as_matrix()
    frame_r = np.einsum("ab,mrb->mra", Q, frame)
    a = pulley_state(B, *args, inward, frame, per_cable=True)
    b = pulley_state(B @ Q.T, A @ Q.T, *args[1:], inward, frame_r, per_cable=True)
    assert np.abs(a.L_TE - b.L_TE).max() < 1e-12 and np.abs(a.gamma - b.gamma).max() < 1e-12
    assert np.abs(a.D @ Q.T - b.D).max() < 1e-12 and np.abs(a.K @ Q.T - b.K).max() < 1e-12
    sa = swivel(B, A, frame, inward, per_cable=True)
    sb = swivel(B @ Q.T, A @ Q.T, frame_r, inward, per_cable=True)
    assert np.abs(np.angle(np.exp(1j * (sa - sb)))).max() < 1e-12


@pytest.mark.parametrize("kind", ["fixed", "SR", "DR"])
def test_identity_frame_equals_todays_model_bit_for_bit(cdpr4, kind):
    r = with_pulleys(cdpr4, kind=kind)
    a = r.arrays
    args = (a.A, a.kind, a.h, a.r_p, a.d, a.inward)
    eye = np.tile(np.eye(3), (4, 1, 1))
    old = total_length_and_direction(PTS, *args)
    new = total_length_and_direction(PTS, *args, eye)
    per = total_length_and_direction(np.repeat(PTS[:, None, :], 4, axis=1), *args, per_cable=True)
    for f in old._fields:
        assert np.array_equal(getattr(old, f), getattr(new, f)), f
        assert np.array_equal(getattr(old, f), getattr(per, f)), f
    st = igm_e(r, PTS)
    assert np.array_equal(swivel(PTS, a.A, None, a.inward), -st.alpha)


def test_wall_pulley_wrap_over_270_is_flagged_and_finite():
    """A pulley with axis +x: an attachment just behind the sheave (w < 0) and between the axis and
    the sheave (s < h, inside its rim) wraps > 270 deg; one well in front wraps less."""
    A = np.array([[0.0, 0.0, 1.0]])
    frame = pulley_frame((1.0, 0.0, 0.0))[None]
    args = (A, np.array([1], dtype=np.int8), np.array([0.05]), np.array([0.05]), np.array([1.0]))
    inward = np.array([[1.0, 0.0]])
    in_front = A + [[0.5, 0.0, -1.0]]  # in front of the wall, below: ordinary wrap
    behind = A + [[-0.04, 0.0, 0.005]]  # w = -0.04 m, s = 5 mm < h: inside the rim
    st = pulley_state(np.array([in_front, behind]), *args, inward, frame, per_cable=True)
    flags = wrap_over_270(st)
    assert not flags[0, 0] and flags[1, 0]
    assert np.isfinite(st.L_TE).all() and (st.gamma[1] > 1.5 * np.pi).all()
