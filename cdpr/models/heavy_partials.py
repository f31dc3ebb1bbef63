"""Exact partial derivatives of the heavy-cable balance at fixed poses (issue 38): each cable's end
force at B_i with respect to B_i, its rest length and its own parameters, the exit point's slide on
the sheave included, by the implicit-function theorem on the per-cable coupled system that
``cables.HeavyCables`` solves by a fixed point.

One cable (``HeavyCables._couple``, ``catenary.cable_state``) has the unknowns z = (P*, H, V_B,
L0_free): the virtual point P* on the catenary's end tangent (the exit point D(P*) is its tangent
point on the sheave, ``pulleys.pulley_state``, and l_dead(P*) = |l_d| + r_p gamma), the end forces and
the free span's unstrained length. With v = D - B, n = |v|, l_v = v . up, l_h e_h = v - l_v up and
u = -(H e_h + V_D up)/T_D (V_D = V_B + w L0_free) the residuals are

    R1 = P* - D - n u                                        (3: P* on the end tangent at D)
    R2 = s(H, V_B, L0_free, w, EA) - (l_h, l_v)              (2: Irvine's span equations)
    R3 = L0_free + l_dead EA/(EA + T_D) - L0                 (1: the split of the rest length)

(fixed pulleys only: R1 = P* - B, as ``HeavyCables`` does not iterate then). For the parameters
q = (B, L0, EA, w, h, r_p, d, A), dz/dq = -(∂R/∂z)^-1 ∂R/∂q, and the end force
F = H e_h + V_B up follows: dF/dq = ∂F/∂z dz/dq + ∂F/∂q. ∂s comes from
``catenary_partials.span_partials``; the derivatives of D and l_dead by P* and the pulley
parameters (the swivel angle, any axis, the DR arm's bisector, the wrap) by forward-mode
differentiation of ``pulleys.pulley_state``'s formulas (``_pulley_jets``).

References
----------
Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (eq. 3-7).
Implicit-function theorem, e.g. J. Nocedal and S. Wright, Numerical Optimization, 2nd ed.,
Springer 2006, A.2.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from cdpr.models.catenary_partials import span_partials

#: Columns of q in ``CablePartialsHeavy.dF``: B_x, B_y, B_z, L0, EA, w, h, r_p, d, A_x, A_y, A_z.
Q_NAMES = ("B_x", "B_y", "B_z", "L0", "EA", "w", "h", "r_p", "d", "A_x", "A_y", "A_z")
_NQ = len(Q_NAMES)
#: Seeds of the pulley jets: P*_x, P*_y, P*_z, h, r_p, d, A_x, A_y, A_z.
_NJ = 9


class _Jet:
    """A value (...) with its derivatives (..., K) by K seeds (forward-mode differentiation)."""

    __slots__ = ("v", "d")

    def __init__(self, v, d):
        self.v, self.d = v, d

    def __add__(self, o):
        if isinstance(o, _Jet):
            return _Jet(self.v + o.v, self.d + o.d)
        return _Jet(self.v + o, self.d)

    def __sub__(self, o):
        if isinstance(o, _Jet):
            return _Jet(self.v - o.v, self.d - o.d)
        return _Jet(self.v - o, self.d)

    def __rsub__(self, o):
        return _Jet(o - self.v, -self.d)

    def __mul__(self, o):
        if isinstance(o, _Jet):
            return _Jet(self.v * o.v, self.d * o.v[..., None] + o.d * self.v[..., None])
        o = np.asarray(o)
        return _Jet(self.v * o, self.d * o[..., None])

    def __truediv__(self, o):
        if isinstance(o, _Jet):
            q = self.v / o.v
            return _Jet(q, (self.d - o.d * q[..., None]) / o.v[..., None])
        o = np.asarray(o)
        return _Jet(self.v / o, self.d / o[..., None])

    def __rtruediv__(self, o):
        q = o / self.v
        return _Jet(q, -self.d * (q / self.v)[..., None])


def _hypot(a, b):
    r = np.hypot(a.v, b.v)
    s = np.where(r > 0.0, r, 1.0)[..., None]
    return _Jet(r, (a.v[..., None] * a.d + b.v[..., None] * b.d) / s)


def _atan2(y, x):
    r2 = x.v * x.v + y.v * y.v
    s = np.where(r2 > 0.0, r2, 1.0)[..., None]
    return _Jet(np.arctan2(y.v, x.v), (x.v[..., None] * y.d - y.v[..., None] * x.d) / s)


def _acos(x):
    c = np.minimum(x.v, 1.0)
    s = np.sqrt(np.maximum(1.0 - c * c, 0.0))
    return _Jet(np.arccos(c), -x.d / np.where(s > 0.0, s, np.inf)[..., None])


def _sqrt(x):
    r = np.sqrt(np.maximum(x.v, 0.0))
    return _Jet(r, 0.5 * x.d / np.where(r > 0.0, r, np.inf)[..., None])


def _cos(x):
    return _Jet(np.cos(x.v), -np.sin(x.v)[..., None] * x.d)


def _sin(x):
    return _Jet(np.sin(x.v), np.cos(x.v)[..., None] * x.d)


def _where(c, a, b):
    return _Jet(np.where(c, a.v, b.v), np.where(c[..., None], a.d, b.d))


def _const(v, shape, seed=None):
    """A parameter (m,) broadcast to ``shape`` (..., m) as a jet, seeded at column ``seed``."""
    v = np.broadcast_to(np.asarray(v, dtype=float), shape)
    d = np.zeros(shape + (_NJ,))
    if seed is not None:
        d[..., seed] = 1.0
    return _Jet(v, d)


def _pulley_jets(Pv, A, kind, h, r_p, d, frame):
    """The exit point D (..., m, 3) [m] and l_dead = |l_d| + r_p gamma (..., m) [m] at the virtual
    points Pv (..., m, 3) [m] and their derivatives (..., m, 3, 9) and (..., m, 9) by P*_xyz, h,
    r_p, d, A_xyz: ``pulleys.pulley_state``'s formulas (plane, sheave centre, tangent points, wrap,
    Paty 2021 eq. 3-7) differentiated forward (no on-axis fallback: B_i off the swivel axis)."""
    shape = Pv.shape[:-1]
    fr = np.broadcast_to(np.eye(3), A.shape[:1] + (3, 3)) if frame is None else frame
    W = []
    for a in range(3):
        dW = np.zeros(shape + (_NJ,))
        dW[..., a] = 1.0
        dW[..., 6 + a] = -1.0
        W.append(_Jet(Pv[..., a] - A[:, a], dW))
    comp = [W[0] * fr[:, r, 0] + W[1] * fr[:, r, 1] + W[2] * fr[:, r, 2] for r in range(3)]
    ws, wt, w_P = comp
    rho = _hypot(ws, wt)
    es0, es1 = ws / rho, wt / rho
    hj, rj, dj = _const(h, shape, 3), _const(r_p, shape, 4), _const(d, shape, 5)
    n_P = _hypot(rho, w_P)
    bs = rho / n_P
    bw = w_P / n_P - 1.0
    nb = _hypot(bs, bw)
    dr = np.broadcast_to(np.asarray(kind) == 2, shape)
    zero = _const(0.0, shape)
    H_s = _where(dr, hj * bs / nb, hj)
    H_w = _where(dr, hj * bw / nb, zero)
    rsP, rwP = rho - H_s, w_P - H_w
    R_P = _hypot(rsP, rwP)
    th_D = _atan2(rwP, rsP) + _acos(rj / R_P)
    rsC, rwC = zero - H_s, zero - dj - H_w
    R_C = _hypot(rsC, rwC)
    th_K = _atan2(rwC, rsC) - _acos(rj / R_C)
    gamma = th_K - th_D
    gamma = _Jet(np.mod(gamma.v, 2.0 * np.pi), gamma.d)  # the wrap in [0, 2 pi), as pulley_state
    l_d = _sqrt(R_C * R_C - rj * rj)
    l_dead = l_d + rj * gamma
    s_D = H_s + rj * _cos(th_D)
    w_D = H_w + rj * _sin(th_D)
    Dv, Dd = [], []
    for a in range(3):
        e = es0 * fr[:, 0, a] + es1 * fr[:, 1, a]
        comp_a = s_D * e + w_D * fr[:, 2, a]
        dA = np.zeros(_NJ)
        dA[6 + a] = 1.0
        Dv.append(A[:, a] + comp_a.v)
        Dd.append(comp_a.d + dA)
    return np.stack(Dv, axis=-1), np.stack(Dd, axis=-2), l_dead.v, l_dead.d


class CablePartialsHeavy(NamedTuple):
    """Every heavy cable's end force at B_i and its exact derivatives (``cable_force_partials``).

    F (..., m, 3) [N]: the force on the platform at B_i; t (..., m) [N]: the tension at B_i;
    dF (..., m, 3, 12): by q = B_x, B_y, B_z [N/m], L0 [N/m], EA [N/N], w [N/(N/m)], h, r_p, d,
    A_x, A_y, A_z [N/m] (``Q_NAMES``); r (..., m, 3) [m]: R b_i."""

    F: np.ndarray
    t: np.ndarray
    dF: np.ndarray
    r: np.ndarray


def cable_force_partials(cab, P, R, L0, x=None):
    """The end force F_i = H e_h + V_B up of every heavy cable at fixed poses and its derivatives by
    B_i, the rest length, EA, w and the cable's pulley parameters, exact: the implicit-function
    theorem on the per-cable coupled system (module docstring) that ``HeavyCables.exit_points``
    solves, so the exit point's slide on the sheave, the swivel and a DR arm's turn are included.

    Parameters
    ----------
    cab : HeavyCables
        The robot's cables.
    P : ndarray (N, 3) [m]
        Platform positions.
    R : ndarray (N, 3, 3) [-]
        Orientations.
    L0 : ndarray (N, m) [m]
        Rest lengths of the whole cables.
    x : dict, optional
        ``cab.exit_points(P, R, L0)`` when already computed (``HeavyCables.evaluate``'s Jacobian).

    Returns
    -------
    CablePartialsHeavy
        F, t, dF (by ``Q_NAMES``), r.

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2; Paty et al. 2021, eq. (3)-(7).
    """
    x = cab.exit_points(P, R, L0) if x is None else x
    st, sp = x["state"], x["state"].span
    H, V_B, V_D, T_D, L0f = sp.H, sp.V_B, sp.V_D, sp.T_D, st.L0_free
    v, l_h, e_h, ell = x["v"], x["l_h"], x["e_h"], x["l_dead"]
    up = cab.up
    w = np.broadcast_to(cab.w, H.shape)
    EA = np.broadcast_to(cab.EA, H.shape)
    n = np.linalg.norm(v, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        u = -(H[..., None] * e_h + V_D[..., None] * up) / T_D[..., None]
    # the virtual point: on the end tangent (the coupling's fixed point), or B itself without it
    Pv = x["D"] + n[..., None] * u if cab.pulleys else P[:, None, :] + x["r"]
    A, kind, h, r_p, d, _, frame = cab.args
    _, dD, _, dell = _pulley_jets(Pv, A, kind, h, r_p, d, frame)
    sh = H.shape
    # derivatives of v = D - B by z = (P*, H/T_D, V_B/T_D, L0_free) and q (module docstring)
    Vz = np.zeros(sh + (3, 6))
    Vq = np.zeros(sh + (3, _NQ))
    Vz[..., :3] = dD[..., :3]
    Vq[..., :3] = -np.eye(3)
    Vq[..., 6:] = dD[..., 3:]
    Dz, Dq = Vz, Vq.copy()
    Dq[..., :3] = 0.0
    flat = np.eye(3) - e_h[..., :, None] * e_h[..., None, :] - up[:, None] * up[None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        flat = flat / l_h[..., None, None]
    nv = v / n[..., None]

    def geo(V):
        return (
            np.einsum("...a,...ak->...k", nv, V),
            np.einsum("...a,...ak->...k", e_h, V),
            np.einsum("a,...ak->...k", up, V),
            flat @ V,
        )

    dn_z, dlh_z, dlv_z, deh_z = geo(Vz)
    dn_q, dlh_q, dlv_q, deh_q = geo(Vq)
    # the catenary's arguments c = (H, V_B, L0_free, w, EA) by z and q; H, V_B scaled by T_D
    Cz = np.zeros(sh + (5, 6))
    Cz[..., 0, 3] = T_D
    Cz[..., 1, 4] = T_D
    Cz[..., 2, 5] = 1.0
    Cq = np.zeros(sh + (5, _NQ))
    Cq[..., 3, 5] = 1.0
    Cq[..., 4, 4] = 1.0
    Sp = span_partials(H, V_B, L0f, w, EA)
    with np.errstate(divide="ignore", invalid="ignore"):
        tD = np.stack([H / T_D, V_D / T_D, w * V_D / T_D, L0f * V_D / T_D, np.zeros(sh)], axis=-1)
        inf = np.isinf(EA)
        rho = np.where(inf, 1.0, EA / (EA + T_D))
        rho_T = np.where(inf, 0.0, -EA / (EA + T_D) ** 2)
        rho_EA = np.where(inf, 0.0, T_D / (EA + T_D) ** 2)
    vD = np.zeros(sh + (5,))
    vD[..., 1] = 1.0
    vD[..., 2] = w
    vD[..., 3] = L0f

    def rows(C, dn, dlh, dlv, deh, Dx, dl_dead, eye_P, eye_L0):
        dTD = np.einsum("...c,...ck->...k", tD, C)
        dVD = np.einsum("...c,...ck->...k", vD, C)
        R2 = np.einsum("...rc,...ck->...rk", Sp, C) - np.stack([dlh, dlv], axis=-2)
        R3 = (
            C[..., 2, :]
            + rho[..., None] * dl_dead
            + ell[..., None] * (rho_T[..., None] * dTD + rho_EA[..., None] * C[..., 4, :])
        )
        R3 = R3 - eye_L0
        with np.errstate(divide="ignore", invalid="ignore"):
            du = (
                -(
                    e_h[..., :, None] * C[..., None, 0, :]
                    + H[..., None, None] * deh
                    + up[:, None] * dVD[..., None, :]
                    + u[..., :, None] * dTD[..., None, :]
                )
                / T_D[..., None, None]
            )
        R1 = eye_P - Dx - u[..., :, None] * dn[..., None, :] - n[..., None, None] * du
        dF = (
            e_h[..., :, None] * C[..., None, 0, :]
            + H[..., None, None] * deh
            + up[:, None] * C[..., None, 1, :]
        )
        return np.concatenate([R1, R2, R3[..., None, :]], axis=-2), dF

    eyeP_z = np.zeros(sh + (3, 6))
    eyeP_z[..., :3] = np.eye(3)
    dell_z = np.zeros(sh + (6,))
    dell_z[..., :3] = dell[..., :3]
    dell_q = np.zeros(sh + (_NQ,))
    dell_q[..., 6:] = dell[..., 3:]
    eyeL0 = np.zeros(_NQ)
    eyeL0[3] = 1.0
    Rz, Fz = rows(Cz, dn_z, dlh_z, dlv_z, deh_z, Dz, dell_z, eyeP_z, 0.0)
    Rq, Fq = rows(Cq, dn_q, dlh_q, dlv_q, deh_q, Dq, dell_q, 0.0, eyeL0)
    if not cab.pulleys:  # no coupling: P* = B
        Rz[..., :3, :] = eyeP_z
        Rq[..., :3, :] = 0.0
        Rq[..., :3, :3] = -np.eye(3)
    # cables where the system is not finite (a slack weightless cable: T_D = 0) get NaN derivatives
    bad = ~(np.isfinite(Rz).all(axis=(-2, -1)) & np.isfinite(Rq).all(axis=(-2, -1)))
    Rz[bad] = np.eye(6)
    dz = -np.linalg.solve(Rz, np.where(bad[..., None, None], 0.0, Rq))
    dz[bad] = np.nan
    dF = Fz @ dz + Fq
    # a slack weightless cable (w = 0 in a robot with heavy cables, chord < L0): no force, and none
    # under a small change (its partials, divided by T_D = 0 above, are NaN there)
    dF = np.where((T_D > 0.0)[..., None, None], dF, 0.0)
    F = H[..., None] * e_h + V_B[..., None] * up
    return CablePartialsHeavy(F=F, t=sp.T_B, dF=dF, r=x["r"])
