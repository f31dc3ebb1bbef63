"""Our SR pulley with h = r_p against the swivel-pulley kinematics of cdpyr and CASPR (issue 17,
docs/spatial.md "Where it equals CASPR's and cdpyr's pulley kinematics").

Each reference is re-derived here as a formula from a reading of its code (nothing of it is copied or
imported), and compared with ``models.pulleys.pulley_state`` at random swivel axes, joint points and
attachments: our L_TE minus the dead length d (cdpyr and CASPR start the cable at the pulley, not at
the winch) equals the reference's length to 1e-12 m.

References
----------
Tempel, P. cdpyr, cdpyr/analysis/kinematics/pulley.py, ``Pulley._backward`` (github.com/cable-robots/cdpyr).
Lau, D. et al. CASPR, src/Model/Cables/CableAttachments/BaseRotatingPulleyAttachment/
BaseRotatingPulleyAttachment.m, ``ComputePulleyLeavingLocation`` (github.com/darwinlau/CASPR).
"""

import numpy as np

from cdpr.models.pulleys import pulley_state, swivel
from cdpr.robot import KIND_CODE, pulley_frame


def cdpyr_pulley(B, A, F, r):
    """cdpyr's inverse kinematics of one swivel pulley of radius r whose frame has the rows F = (x, y, z)
    (z the swivel axis) and origin A, the point where the cable enters on the axis.

    With v = F (B - A): swivel = atan2(v_y, v_x); in the cable plane (x' toward B, z) the roller centre
    is at (r, 0) and B at q = (hypot(v_x, v_y) - r, v_z) from it; the straight length is
    l = sqrt(|q|^2 - r^2); the leave angle theta solves r cos(theta) + l sin(theta) = q_x,
    -l cos(theta) + r sin(theta) = q_z; the wrap is pi - theta and the length l + r (pi - theta).

    Returns length [m], wrap [rad], swivel [rad] and the leave point (3,) [m] in the base frame.
    """
    v = F @ (B - A)
    sw = np.arctan2(v[1], v[0])
    qx, qz = np.hypot(v[0], v[1]) - r, v[2]
    q2 = qx * qx + qz * qz
    ell = np.sqrt(q2 - r * r)
    theta = np.arctan2((ell * qx + r * qz) / q2, (r * qx - ell * qz) / q2)
    wrap = np.pi - theta
    leave = np.array([r + r * np.cos(theta), 0.0, r * np.sin(theta)])  # cable frame (x', y', z)
    Rz = np.array([[np.cos(sw), -np.sin(sw), 0.0], [np.sin(sw), np.cos(sw), 0.0], [0.0, 0.0, 1.0]])
    return ell + r * wrap, wrap, sw, A + F.T @ (Rz @ leave)


def caspr_pulley(B, r_F, v_F, R):
    """CASPR's base rotating pulley: entry point r_F, entry direction v_F, radius R.

    n = v_F x (B - r_F); centre r_C = r_F + R (n x v_F)/|n x v_F|; with rho = R/|B - r_C| the leave
    point r_A = r_C + rho^2 (B - r_C) - rho sqrt(1 - rho^2) (n/|n|) x (B - r_C); the arc is
    R arccos(n_1 . n_2), n_1, n_2 the unit vectors from r_C to r_F and to r_A (at most pi R), and the
    length the arc plus |B - r_A|.

    Returns length [m] and the leave point r_A (3,) [m].
    """
    n = np.cross(v_F, B - r_F)
    v_FC = np.cross(n, v_F)
    r_C = r_F + R * v_FC / np.linalg.norm(v_FC)
    rho = R / np.linalg.norm(B - r_C)
    r_A = r_C + rho**2 * (B - r_C) - rho * np.sqrt(1 - rho**2) * np.cross(n / np.linalg.norm(n), B - r_C)
    n1, n2 = (r_F - r_C) / R, (r_A - r_C) / R
    return R * np.arccos(np.clip(n1 @ n2, -1.0, 1.0)) + np.linalg.norm(B - r_A), r_A


def _random_case(seed, m=8, n=60):
    """m SR pulleys with h = r_p at random axes and joint points, n attachments each: B = A + s e + w k
    (e a random unit vector perpendicular to k, 0.02 <= s <= 2 m, |w| <= 2 m) outside the sheave."""
    g = np.random.default_rng(seed)
    axis = g.normal(size=(m, 3))
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    frame = np.array([pulley_frame(a) for a in axis])
    A = g.uniform(-3, 3, size=(m, 3))
    r = g.uniform(0.02, 0.2, size=m)
    d = g.uniform(0.5, 3.0, size=m)
    e = g.normal(size=(n, m, 3))
    e -= np.einsum("nma,ma->nm", e, axis)[..., None] * axis
    e /= np.linalg.norm(e, axis=-1, keepdims=True)
    s, w = g.uniform(0.02, 2.0, size=(n, m)), g.uniform(-2.0, 2.0, size=(n, m))
    far = np.hypot(s - r, w) > 1.05 * r  # outside the sheave (no tangent from inside)
    s = np.where(far, s, s + 2.2 * r)
    B = A + s[..., None] * e + w[..., None] * axis
    st = pulley_state(
        B,
        A,
        np.full(m, KIND_CODE["SR"], dtype=np.int8),
        r,
        r,
        d,
        np.tile([1.0, 0.0], (m, 1)),
        frame,
        per_cable=True,
    )
    return A, axis, frame, r, d, B, st


def test_sr_with_h_equal_r_p_is_cdpyrs_pulley_at_every_wrap():
    A, axis, frame, r, d, B, st = _random_case(2024)
    sw = swivel(B, A, frame, np.tile([1.0, 0.0], (len(A), 1)), per_cable=True)
    assert np.abs(st.l_d - d).max() < 1e-12  # K = A: the cable enters on the axis
    n, m = B.shape[:2]
    for a in range(n):
        for i in range(m):
            L, wrap, s_i, leave = cdpyr_pulley(B[a, i], A[i], frame[i], r[i])
            assert abs(st.L_TE[a, i] - d[i] - L) < 1e-12
            assert abs(st.gamma[a, i] - wrap) < 1e-12
            assert abs(np.angle(np.exp(1j * (sw[a, i] - s_i)))) < 1e-12
            assert np.abs(st.D[a, i] - leave).max() < 1e-12
    # the comparison covers wraps beyond 180 deg: cdpyr's wrap pi - atan2(...) is not capped either
    assert (st.gamma > np.pi).sum() >= 10 and (st.gamma < 0.5 * np.pi).sum() >= 10


def test_sr_with_h_equal_r_p_is_caspr_base_rotating_pulley_up_to_180_degrees():
    A, axis, frame, r, d, B, st = _random_case(7)
    n, m = B.shape[:2]
    checked = beyond = 0
    for a in range(n):
        for i in range(m):
            L, r_A = caspr_pulley(B[a, i], A[i], axis[i], r[i])
            if st.gamma[a, i] <= np.pi:
                assert abs(st.L_TE[a, i] - d[i] - L) < 1e-12
                assert np.abs(st.D[a, i] - r_A).max() < 1e-12
                checked += 1
            else:  # same tangent point; CASPR's arccos counts the arc the short way round
                assert np.abs(st.D[a, i] - r_A).max() < 1e-12
                arc = r[i] * (2 * np.pi - st.gamma[a, i])
                assert abs(L - (st.l_E[a, i] + arc)) < 1e-12
                beyond += 1
    assert checked > 200 and beyond >= 10
