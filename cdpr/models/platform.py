"""A rigid 6-DoF platform: pose, attachment points, wrench matrix, external wrench, orientation error.

The pose is the reference point p of the platform (base frame) and its orientation R (active,
base-frame rotation vector r: R = exp([r]x), ``Rotation.from_rotvec``). Cable i is attached at
B_i = p + R b_i with b_i in the platform frame; the centre of mass is c (platform frame), gravity
acts there. A point-mass platform is the special case b_i = 0, c = 0 (then R plays no part).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (notation b_i).

Pott, A. (2018). Cable-Driven Parallel Robots: Theory and Application. Springer (the wrench matrix,
section 3.3).
"""

from __future__ import annotations

import numpy as np


def skew(v):
    """The cross-product matrix [v]x with [v]x w = v x w (linear algebra, no paper equation).

    Parameters
    ----------
    v : array_like (..., 3) [any unit]
        Vectors.

    Returns
    -------
    S : ndarray (..., 3, 3) [unit of v]
        Skew-symmetric matrices.
    """
    v = np.asarray(v, dtype=float)
    z = np.zeros(v.shape[:-1])
    return np.stack(
        [
            np.stack([z, -v[..., 2], v[..., 1]], axis=-1),
            np.stack([v[..., 2], z, -v[..., 0]], axis=-1),
            np.stack([-v[..., 1], v[..., 0], z], axis=-1),
        ],
        axis=-2,
    )


def rotation_matrix(rotvec):
    """Rodrigues' formula R = I + sin(a)/a [r]x + (1 - cos a)/a^2 [r]x^2, a = |r|.

    .. math:: R = \\exp([r]_\\times)

    Parameters
    ----------
    rotvec : array_like (..., 3) [rad]
        Rotation vectors (active, base-frame components; the convention of
        ``scipy.spatial.transform.Rotation.from_rotvec``).

    Returns
    -------
    R : ndarray (..., 3, 3) [-]
        Rotation matrices.

    References
    ----------
    Murray, Li, Sastry (1994), A Mathematical Introduction to Robotic Manipulation, eq. (2.14).
    """
    r = np.asarray(rotvec, dtype=float)
    a = np.linalg.norm(r, axis=-1)
    small = a < 1e-8
    a_safe = np.where(small, 1.0, a)
    s = np.where(small, 1.0 - a * a / 6.0, np.sin(a) / a_safe)
    c = np.where(small, 0.5 - a * a / 24.0, (1.0 - np.cos(a)) / (a_safe * a_safe))
    K = skew(r)
    return np.eye(3) + s[..., None, None] * K + c[..., None, None] * (K @ K)


def rotvec_of(R):
    """Rotation vector of rotation matrices (inverse of ``rotation_matrix``; scipy's as_rotvec).

    Parameters
    ----------
    R : array_like (..., 3, 3) [-]
        Rotation matrices.

    Returns
    -------
    rotvec : ndarray (..., 3) [rad]
        |rotvec| in [0, pi]; NaN where R is not finite.
    """
    R = np.asarray(R, dtype=float)
    flat = R.reshape(-1, 3, 3)
    out = np.full((len(flat), 3), np.nan)  # a pose that is not finite (a failed solve) stays NaN
    ok = np.isfinite(flat).all(axis=(1, 2))
    if ok.any():
        from scipy.spatial.transform import Rotation  # lazy: scipy.spatial is 0.17 s of start-up

        out[ok] = Rotation.from_matrix(flat[ok]).as_rotvec()
    return out.reshape(R.shape[:-1])


def attachment_points(p, R, b):
    """B_i = p + R b_i, the cables' attachment points in the base frame.

    .. math:: B_i = p + R\\, b_i

    Parameters
    ----------
    p : array_like (..., 3) [m]
        Reference point of the platform.
    R : array_like (..., 3, 3) [-]
        Orientation.
    b : array_like (m, 3) [m]
        Attachment points in the platform frame.

    Returns
    -------
    B : ndarray (..., m, 3) [m]
        Attachment points; r = B - p = R b_i is ``B - p[..., None, :]``.

    References
    ----------
    Paty et al. 2021, section 2.1 (b_i).
    """
    r = np.einsum("...ab,mb->...ma", np.asarray(R, dtype=float), np.asarray(b, dtype=float))
    return np.asarray(p, dtype=float)[..., None, :] + r


def wrench_matrix(u, r):
    """The 6 x m wrench matrix W, column i = [u_i ; r_i x u_i] (moments about p).

    .. math:: W = \\begin{bmatrix} u_1 & \\cdots & u_m \\\\ r_1 \\times u_1 & \\cdots & r_m \\times u_m \\end{bmatrix},
        \\quad r_i = R b_i, \\quad W t + w_{ext} = 0

    Parameters
    ----------
    u : array_like (..., m, 3) [-]
        Unit vectors from B_i toward the exit points D_i.
    r : array_like (..., m, 3) [m]
        R b_i.

    Returns
    -------
    W : ndarray (..., 6, m) [-, m]
        Force rows (3) and moment rows (3).

    References
    ----------
    Pott 2018, eq. (3.31); Paty et al. 2021, eq. (11)-(12) (force rows, b_i = 0).
    """
    u = np.asarray(u, dtype=float)
    col = np.concatenate([u, np.cross(np.asarray(r, dtype=float), u)], axis=-1)
    return np.swapaxes(col, -1, -2)


def external_wrench(mass, g, com, R, down=(0.0, 0.0, -1.0), wrench=None):
    """Gravity wrench on the platform about p: [f ; (R c) x f], f = M g ``down`` = (0, 0, -M g),
    plus an external wrench w_e = [F_e ; M_e] beside gravity (force at p and moment about p, both
    in the base frame: constant under the platform's rotation).

    .. math:: w_{ext} = \\begin{bmatrix} f \\\\ (R c) \\times f \\end{bmatrix} + w_e

    Parameters
    ----------
    mass : float [kg]
        Platform mass M.
    g : float [m/s^2]
        Gravity.
    com : array_like (3,) [m]
        Centre of mass c in the platform frame.
    R : array_like (..., 3, 3) [-]
        Orientation.
    down : array_like (3,) [-]
        Unit vector of gravity in the base frame (``Platform.down``, -z).
    wrench : array_like (6,) [N, N m], optional
        External wrench beside gravity (``Platform.wrench``); None or zero: gravity alone.

    Returns
    -------
    w_ext : ndarray (..., 6) [N, N m]
        Force and moment.

    References
    ----------
    Pott 2018, section 3.3 (the applied wrench).
    """
    R = np.asarray(R, dtype=float)
    f = np.broadcast_to(mass * g * np.asarray(down, dtype=float), R.shape[:-2] + (3,))
    rc = np.einsum("...ab,b->...a", R, np.asarray(com, dtype=float))
    w = np.concatenate([f, np.cross(rc, f)], axis=-1)
    if wrench is not None and np.any(wrench):
        w = w + np.asarray(wrench, dtype=float)
    return w


def rotation_error(R_s, R_d):
    """delta phi = the rotation angle of R_s R_d^T [rad] (the orientation error of the pose).

    .. math:: \\delta\\varphi = \\arccos\\left(\\frac{\\operatorname{tr}(R_s R_d^T) - 1}{2}\\right)

    computed as atan2(|v|/2, (tr - 1)/2), v the axial vector of Q - Q^T, Q = R_s R_d^T (accurate
    near 0, where arccos is not).

    Parameters
    ----------
    R_s : array_like (..., 3, 3) [-]
        Reached orientation.
    R_d : array_like (..., 3, 3) [-]
        Desired orientation.

    Returns
    -------
    dphi : ndarray (...) [rad]
        In [0, pi].

    References
    ----------
    Murray, Li, Sastry (1994), eq. (2.17).
    """
    Q = np.asarray(R_s, dtype=float) @ np.swapaxes(np.asarray(R_d, dtype=float), -1, -2)
    v = np.stack([Q[..., 2, 1] - Q[..., 1, 2], Q[..., 0, 2] - Q[..., 2, 0], Q[..., 1, 0] - Q[..., 0, 1]], -1)
    tr = Q[..., 0, 0] + Q[..., 1, 1] + Q[..., 2, 2]
    return np.arctan2(0.5 * np.linalg.norm(v, axis=-1), 0.5 * (tr - 1.0))


def pose_arrays(p, rotvec=None):
    """Positions and orientations of poses given as positions and rotation vectors, or as
    (x, y, z, rx, ry, rz) rows (no paper equation).

    Parameters
    ----------
    p : array_like (N, 3) or (N, 6) [m, rad]
        Positions, or poses (x, y, z, rx, ry, rz).
    rotvec : array_like (N, 3) or (3,) [rad], optional
        Rotation vectors (default identity; ignored when p holds poses).

    Returns
    -------
    p : ndarray (N, 3) [m]
    R : ndarray (N, 3, 3) [-]
    """
    p = np.atleast_2d(np.asarray(p, dtype=float))
    if p.shape[1] == 6:
        p, rotvec = p[:, :3], p[:, 3:]
    rv = np.zeros_like(p) if rotvec is None else np.broadcast_to(np.asarray(rotvec, dtype=float), p.shape)
    return np.ascontiguousarray(p), rotation_matrix(rv)
