"""The cables' pull on the platform at poses: force and moment balance, potential energy and the
analytic Jacobian of m cables with pulleys, for the physical equilibrium (``equilibrium``) and the
sensitivities (``sensitivity``).

``Cables`` are massless Hooke cables (Paty et al. 2021, eq. 10-13: t_i = (E_i S_i / L0_i)
max(0, L_TE,i - L0_i) along u_i); ``HeavyCables`` have weight (``cable.linear_density_kg_m``): each
cable's force on the platform at B_i is the end force of Irvine's elastic catenary from B_i to the
sheave exit point D_i (``catenary``). The point mass is the rigid platform with b_i = 0, c = 0; the
massless cable the heavy one with w = 0. The solver that uses them, and the equations in full, are
``equilibrium``'s.

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (eq. 2-5, 10-14).

Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
"""

from __future__ import annotations

import numpy as np

from cdpr.models.catenary import (
    angle_f_deg,
    arc_minus_chord,
    cable_energy,
    cable_state,
    cable_stiffness,
    flexibility,
    sag,
    span_equations,
)
from cdpr.models.heavy_partials import cable_force_partials
from cdpr.models.inverse import pulley_args
from cdpr.models.platform import skew
from cdpr.models.pulleys import SWIVEL_RHO_MIN, pulley_state, total_length_and_direction
from cdpr.models.statics import direction_gradient, length_gradient

#: A point is balanced when |F| <= FTOL_REL |w_ext|.
FTOL_REL = 1e-10


class Cables:
    """Force/moment balance, energy and Jacobian of a robot's cables at poses."""

    def __init__(self, robot):
        a = robot.arrays
        self.robot = robot
        self.args = pulley_args(robot)
        self.b, self.com = a.b, a.com
        self.ES = a.ES
        plat = robot.platform
        size = max(float(np.linalg.norm(a.b, axis=1).max()), float(np.linalg.norm(a.com)))
        self.size = size if size > 0 else 1.0
        if robot.point_mass:  # gravity and the external force both act at p: one force f
            self.f, self.fe, self.me = plat.w_ext, np.zeros(3), np.zeros(3)
        else:  # gravity f at the centre of mass, the external wrench (fe, me) at p
            self.f = plat.gravity_force
            self.fe = np.asarray(plat.wrench[:3], dtype=float)
            self.me = np.asarray(plat.wrench[3:], dtype=float)
        #: True when the rigid platform carries an external wrench (the compiled kernels refuse it).
        self.wrench = bool(self.fe.any() or self.me.any())
        scale = float(np.linalg.norm(self.f))
        if plat.has_wrench:  # balanced relative to the largest load (gravity may be cancelled)
            scale = max(
                scale,
                float(np.linalg.norm(plat.gravity_force)),
                float(np.linalg.norm(self.fe)),
                float(np.linalg.norm(self.me)) / self.size,
            )
        self.ftol = FTOL_REL * scale
        self.rigid = not robot.point_mass
        self.suspended = robot.suspended_point_mass
        self.z_top = float(a.A[:, 2].min())

    def evaluate(self, p, R, L0, p_ref, jacobian=True):
        """Cables at poses (p (N, 3), R (N, 3, 3)) with rest lengths L0 (N, m): F, M (N, 3), t (N, m),
        merit V (N,) [J] relative to p_ref (N, 3) and, with ``jacobian``, Fn, J (N, 6, 6), grad (N, 6)
        and kappa (N, 2) (stiffness bounds of translation and rotation)."""
        r = np.einsum("nab,mb->nma", R, self.b)
        B = p[:, None, :] + r
        g = total_length_and_direction(B, *self.args, per_cable=True)
        e = g.L_TE - L0
        k = self.ES / L0
        taut = e > 0.0
        t = np.where(taut, k * e, 0.0)
        rc = R @ self.com
        F = np.einsum("nj,nja->na", t, g.u) + self.f
        M = np.einsum("nj,nja->na", t, np.cross(r, g.u)) + np.cross(rc, self.f)
        merit = -(p - p_ref + rc) @ self.f + 0.5 * (k * np.where(taut, e, 0.0) ** 2).sum(axis=1)
        if self.wrench:
            F, M, merit = self._add_wrench(F, M, merit, p, p_ref)
        if self.suspended:
            merit = np.where(p[:, 2] < self.z_top, merit, np.inf)
        out = {"F": F, "M": M, "t": t, "merit": merit, "g": g}
        if jacobian:
            act = e >= 0.0
            none = ~act.any(axis=1)
            act[none] = True  # no cable taut: Hooke extended to compression (as the point-mass mode)
            tc = np.where(none[:, None], k * e, t)
            Fn = np.einsum("nj,nja->na", tc, g.u) + self.f
            Mn = np.einsum("nj,nja->na", tc, np.cross(r, g.u)) + np.cross(rc, self.f)
            if self.wrench:
                Fn, Mn = Fn + self.fe, Mn + self.me
            out["Fn"] = np.concatenate(
                [np.where(none[:, None], Fn, F), np.where(none[:, None], Mn, M)], axis=1
            )
            ka = k * act
            dL = length_gradient(g)
            out["J"] = _jacobian(t, direction_gradient(g), ka, g.u, dL, r, rc, self.f)
            out["grad"] = np.concatenate(
                [np.einsum("nj,nja->na", t, dL) - self.f, np.einsum("nj,nja->na", t, np.cross(r, dL))], axis=1
            )
            out["grad"][:, 3:] -= np.cross(rc, self.f)
            if self.wrench:  # minus the generalised force of the external wrench (module docstring)
                out["grad"] -= np.concatenate([self.fe, self.me])
            out["kappa"] = _kappa(ka + t / g.l_E, t, r, rc, self.f)
        return out

    def _add_wrench(self, F, M, merit, p, p_ref):
        """The external wrench of a rigid platform at p: F + fe, M + me and the merit with the
        force's potential -fe . (p - p_ref). A constant world-frame moment has no potential (its
        work over a rotation depends on the path): the merit leaves it out and the line search adds
        its work along each trial step (``equilibrium._newton``)."""
        return F + self.fe, M + self.me, merit - (p - p_ref) @ self.fe


class HeavyCables(Cables):
    """``Cables`` whose cables have weight (``cable.linear_density_kg_m``, issue 38): each cable's
    force on the platform at B_i is the end force of Irvine's elastic catenary from B_i to the exit
    point D_i (``catenary.cable_state``, H toward D_i horizontally and V_B up, "up" against gravity),
    the dead length and the wrapped arc carrying the tension at D_i (their weight neglected).

    Pulley coupling (``exit_points``, ``_couple``): the cable leaves the sheave along the catenary's
    end tangent u_i at D_i, tangent to the sheave circle in the sheave plane. D_i is the tangent point,
    in the massless pulley model (``pulleys.pulley_state``), of the virtual point
    P*_i = D_i + |B_i - D_i| u_i on that tangent line: the sheave plane then contains the swivel
    axis and u_i (the swivel angle that puts the end tangent in the sheave plane, for any axis), and
    a DR arm bisects the strand to the winch and the direction of P*_i (Paty 2021's rule with P*_i for
    B_i). The wrap gamma_i and |l_d| are the massless model's at P*_i, and the dead part's stretched
    length is |l_d| + r_p gamma. A fixed point on P*_i from B_i (its contraction is of the order
    r_p / |B_i - D_i|). Fixed, SR and DR pulleys, any swivel axis. With w = 0, P*_i = B_i: the
    massless model computed through the catenary (``heavy=True`` of ``solve``, for the tests).

    The Jacobian (``evaluate``'s ``exact``) is exact near the answer: each cable's dF_i/dB_i from
    ``heavy_partials.cable_force_partials`` (the implicit-function theorem on the cable's coupled
    system: D_i's slide on the sheave, the swivel and a DR arm's turn), so Newton converges
    quadratically there; for its longer steps ``equilibrium._newton`` takes the cheaper form with
    D_i's turn with the swivel only (relative error r_p / |B_i - D_i|). The merit is the energy (``catenary.cable_energy`` plus the free span's weight at the
    exit point's height above A_i): for fixed pulleys its gradient is minus the wrench exactly;
    with SR pulleys the weightless dead part makes the model's forces not exactly conservative and
    the difference is of order w r_p times the dead part's compliance (the merit serves the line
    search only, as for DR pulleys in the massless model)."""

    def __init__(self, robot):
        super().__init__(robot)
        a = robot.arrays
        down = np.asarray(robot.platform.down, dtype=float)
        self.up = -down / np.linalg.norm(down)
        self.A, self.w, self.EA = a.A, a.w, a.ES
        self.axis, self.r_p = a.axis, a.r_p
        self.pulleys = bool((a.kind != 0).any())

    def exit_points(self, p, R, L0, maxiter=60):
        """The exit points D_i and the catenaries at poses (p (N, 3), R (N, 3, 3)) under rest
        lengths L0 (N, m) (the pulley coupling of the class docstring).

        Parameters
        ----------
        p : ndarray (N, 3) [m]
            Platform positions.
        R : ndarray (N, 3, 3) [-]
            Platform orientations.
        L0 : ndarray (N, m) [m]
            Rest lengths of the whole cables.
        maxiter : int
            Cap of the fixed point's iterations.

        Returns
        -------
        dict
            r (N, m, 3) [m] = R b_i; D (N, m, 3) [m] the exit points; v = D - B (N, m, 3) [m]; l_h, l_v (N, m) [m]; e_h (N, m, 3) the
            horizontal unit vector from B_i toward D_i; l_dead (N, m) [m] = |l_d| + r_p gamma;
            gamma (N, m) [rad]; state (``catenary.CableState``); swivel (N, m) = D_s/rho and
            e_perp (N, m, 3) (the plane's turn with B_i); iterations (fixed point).
        """
        r = np.einsum("nab,mb->nma", R, self.b)
        B = p[:, None, :] + r
        box = {"start": None}

        def span(l_h, l_v, ell):
            st = cable_state(l_h, l_v, L0, ell, self.w, self.EA, start=box["start"])
            box["start"] = (st.span.H, st.span.V_B)
            return st, st.span.H, st.span.V_D, st.span.T_D

        x = self._couple(B, span, maxiter)
        x.update(r=r)
        return x

    def _couple(self, B, span, maxiter):
        """The pulley coupling at the attachment points B (N, m, 3) for the span solver ``span``
        ((l_h, l_v, l_dead) -> (solved, H, V_D, T_D)): the exit point D_i is the tangent point, on
        the sheave of the massless pulley model, of the virtual point P*_i = D_i + |B_i - D_i| u_i on
        the catenary's end tangent u_i at D_i (toward the platform); so the sheave plane contains the
        swivel axis and u_i (the swivel angle that puts the end tangent in the sheave plane, any axis),
        u_i touches the sheave circle at D_i, and a DR arm bisects the strand to the winch and the
        direction of P*_i (Paty 2021's rule, with P*_i for B_i). At w = 0, P*_i = B_i: the massless
        model. Fixed point on P*_i from B_i, contraction of the order r_p / |B_i - D_i|; it stops when
        P* moves by at most 1e-15 (1 + max |v|), or when its moves stop shrinking within 1e-12
        (1 + max |v|) (round-off of the catenary's Newton), as the compiled twin."""
        k = np.broadcast_to(self.axis, B.shape)
        Pv = B
        it = 0
        moved_prev = np.inf
        for it in range(1, maxiter + 1):
            ps = pulley_state(Pv, *self.args, per_cable=True)
            ell = ps.l_d + self.r_p * ps.gamma
            v, l_h, l_v, e_h = self.spans(ps.D, B)
            st, H, V_D, T_D = span(l_h, l_v, ell)
            if not self.pulleys:
                break
            with np.errstate(invalid="ignore", divide="ignore"):
                u = -(H[..., None] * e_h + V_D[..., None] * self.up) / T_D[..., None]
            ok = (T_D > 0.0) & np.isfinite(u).all(axis=-1)
            Pv_new = np.where(ok[..., None], ps.D + np.linalg.norm(v, axis=-1)[..., None] * u, B)
            moved = np.linalg.norm(Pv_new - Pv, axis=-1).max(initial=0.0)
            Pv = Pv_new
            scale = 1.0 + float(np.abs(v).max(initial=0.0))
            # converged, or at round-off: within 1e-12 of the lengths the catenary's own Newton leaves
            # ~1e-12 m of noise in P*, so the moves stop shrinking there (the compiled twin's rule)
            if moved <= 1e-15 * scale or (moved >= moved_prev and moved <= 1e-12 * scale):
                ps = pulley_state(Pv, *self.args, per_cable=True)
                ell = ps.l_d + self.r_p * ps.gamma
                v, l_h, l_v, e_h = self.spans(ps.D, B)
                st, H, V_D, T_D = span(l_h, l_v, ell)
                break
            moved_prev = moved
        e_s = ps.e_s3
        e_perp = np.cross(k, e_s)
        BA = B - self.A
        rho = np.linalg.norm(BA - np.einsum("nma,nma->nm", BA, k)[..., None] * k, axis=-1)
        Ds = np.einsum("nma,nma->nm", ps.D - self.A, e_s)
        swivel = np.where(rho > SWIVEL_RHO_MIN, Ds / np.where(rho > 0.0, rho, 1.0), 0.0)
        return {
            "D": ps.D,
            "v": v,
            "l_h": l_h,
            "l_v": l_v,
            "e_h": e_h,
            "l_dead": ell,
            "gamma": ps.gamma,
            "state": st,
            "swivel": swivel,
            "e_perp": e_perp,
            "iterations": it,
            "T_D": T_D,
            "V_D": V_D,
        }

    def inverse(self, p, R, t, maxiter=60):
        """The heavy inverse of every cable at poses: the exit points D_i, the catenaries that carry
        the tensions t_i at B_i (``span_for_tension``) and the whole cables' rest lengths
        L0_i = L0_free,i + l_dead,i / (1 + T_D,i/EA_i) (``catenary.cable_state``'s split), with the
        pulley coupling of ``exit_points`` (D_i where the catenary's end tangent touches the sheave,
        solved by the same fixed point). ``exit_points`` under these L0 gives back the same D_i and
        the tensions t_i at B_i.

        Parameters
        ----------
        p : ndarray (N, 3) [m]
            Platform positions.
        R : ndarray (N, 3, 3) [-]
            Platform orientations.
        t : ndarray (N, m) [N]
            Tensions at B_i (> 0).
        maxiter : int
            Cap of the fixed point's iterations (SR pulleys).

        Returns
        -------
        dict
            r (N, m, 3) [m] = R b_i; D (N, m, 3) [m]; l_h, l_v (N, m) [m]; e_h (N, m, 3); H, V_B,
            V_D, T_D (N, m) [N]; f (N, m, 3) [-] the unit force on the platform at B_i; L0_free, L0
            (N, m) [m]; l_dead (N, m) [m]; gamma (N, m) [rad]; converged (N, m) bool;
            iterations (fixed point).
        """
        t = np.asarray(t, dtype=float)
        r = np.einsum("nab,mb->nma", R, self.b)
        B = p[:, None, :] + r

        def span(l_h, l_v, ell):
            H, V_B, L0f, conv, _ = span_for_tension(l_h, l_v, t, self.w, self.EA)
            V_D = V_B + self.w * L0f
            return (H, V_B, L0f, conv), H, V_D, np.hypot(H, V_D)

        x = self._couple(B, span, maxiter)
        (H, V_B, L0f, conv), ell, T_D = x["state"], x["l_dead"], x["T_D"]
        with np.errstate(invalid="ignore"):
            L0 = L0f + ell * np.where(np.isinf(self.EA), 1.0, self.EA / (self.EA + T_D))
            f = (H[..., None] * x["e_h"] + V_B[..., None] * self.up) / t[..., None]
        return {
            "r": r,
            "D": x["D"],
            "l_h": x["l_h"],
            "l_v": x["l_v"],
            "e_h": x["e_h"],
            "H": H,
            "V_B": V_B,
            "V_D": x["V_D"],
            "T_D": T_D,
            "f": f,
            "L0_free": L0f,
            "L0": L0,
            "l_dead": ell,
            "gamma": x["gamma"],
            "converged": conv,
            "iterations": x["iterations"],
        }

    def spans(self, D, B):
        """v = D - B, l_h, l_v [m] and e_h, the horizontal unit vector from B toward D."""
        v = D - B
        l_v = v @ self.up
        hv = v - l_v[..., None] * self.up
        l_h = np.linalg.norm(hv, axis=-1)
        e_h = hv / np.where(l_h > 0.0, l_h, 1.0)[..., None]
        return v, l_h, l_v, e_h

    def evaluate(self, p, R, L0, p_ref, jacobian=True, exact=True):
        """As ``Cables.evaluate``, with each cable's force the catenary's end force at B_i and t_i its
        tension at B_i. ``exact`` (bool, or (N,) bool per pose): each pulley cable's dF_i/dB_i in the
        Jacobian is exact (``heavy_partials.cable_force_partials``: the exit point's slide on the
        sheave, the swivel and a DR arm's turn), else it takes D's turn with the swivel only (of
        relative error r_p / |B_i - D_i|, half the cost: ``equilibrium._newton`` uses it for its
        steps longer than ``LS_SKIP``, the exact one near the answer)."""
        x = self.exit_points(p, R, L0)
        r, l_h, l_v, e_h, st = x["r"], x["l_h"], x["l_v"], x["e_h"], x["state"]
        sp = st.span
        Fi = sp.H[..., None] * e_h + sp.V_B[..., None] * self.up
        rc = R @ self.com
        F = Fi.sum(axis=1) + self.f
        M = np.cross(r, Fi).sum(axis=1) + np.cross(rc, self.f)
        if self.wrench:
            F, M, wrench_merit = self._add_wrench(F, M, 0.0, p, p_ref)
        U = cable_energy(st, l_h, l_v, x["l_dead"], self.w, self.EA)
        # the free span's weight at the exit point's height above A_i (0 for fixed pulleys): the
        # weightless dead part makes the model's forces not exactly conservative, and with this term
        # the merit's gradient is minus the wrench up to w (D - A).up dL0_free/dB (r_p times the
        # dead part's compliance; the slide of D on the sheave alone would leave w L0_free dz_D/dB)
        U = U + self.w * st.L0_free * ((x["D"] - self.A) @ self.up)
        merit = -(p - p_ref + rc) @ self.f + U.sum(axis=1)
        if self.wrench:
            merit = merit + wrench_merit
        merit = np.where(np.isfinite(merit), merit, np.inf)
        if self.suspended:
            merit = np.where(p[:, 2] < self.z_top, merit, np.inf)
        t = sp.T_B
        out = {"F": F, "M": M, "t": t, "merit": merit, "g": None}
        if jacobian:
            K = cable_stiffness(st, x["l_dead"], self.w, self.EA)
            up = self.up
            flat = np.eye(3) - e_h[..., :, None] * e_h[..., None, :] - up[:, None] * up[None, :]
            with np.errstate(divide="ignore", invalid="ignore"):
                turn = np.where(l_h > 1e-12 * (1.0 + np.abs(l_v)), sp.H / l_h, K[..., 0, 0])
            dFdv = (
                e_h[..., :, None] * (K[..., 0, 0, None] * e_h + K[..., 0, 1, None] * up)[..., None, :]
                + up[:, None] * (K[..., 1, 0, None] * e_h + K[..., 1, 1, None] * up)[..., None, :]
                + turn[..., None, None] * flat
            )
            ep = x["e_perp"]
            dvdB = -np.eye(3) + x["swivel"][..., None, None] * ep[..., :, None] * ep[..., None, :]
            G = dFdv @ dvdB  # dF_i/dB_i with D turning with the swivel only (fixed pulleys: exact)
            ex = np.broadcast_to(np.asarray(exact, dtype=bool), p.shape[:1])
            if self.pulleys and ex.any():  # exact: D's slide on the sheave, a DR arm's turn
                xs = x if ex.all() else {k: _rows(v, ex) for k, v in x.items()}
                with np.errstate(divide="ignore", invalid="ignore"):
                    Gx = cable_force_partials(self, p[ex], R[ex], L0[ex], x=xs).dF[..., :3]
                G[ex] = np.where(np.isfinite(Gx).all(axis=(-2, -1))[..., None, None], Gx, G[ex])
            out["Fn"] = np.concatenate([F, M], axis=1)
            out["J"] = _jacobian_forces(G, Fi, r, rc, self.f)
            out["grad"] = -out["Fn"]  # fixed and SR pulleys: the energy's gradient is minus the wrench
            # (with an external wrench: minus the generalised force, the moment's work as in Cables)
            out["kappa"] = _kappa(
                np.abs(K[..., 0, 0]) + np.abs(K[..., 1, 1]) + np.abs(turn), t, r, rc, self.f
            )
        return out


def _kappa(stiff, t, r, rc, f):
    """The stiffness bounds kappa (N, 2) of ``evaluate``: translation sum_i k_i and rotation
    sum_i (k_i |r_i|^2 + t_i |r_i|) + |f| |rc|, from each cable's stiffness bound k_i (N, m) [N/m],
    tension t (N, m) [N] and arm r (N, m, 3) [m]; rc (N, 3) [m] the centre of mass's arm, f (3,) [N]
    the platform's weight."""
    rr = np.einsum("nma,nma->nm", r, r)
    return np.stack(
        [
            stiff.sum(axis=1),
            (stiff * rr + t * np.sqrt(rr)).sum(axis=1) + np.linalg.norm(f) * np.linalg.norm(rc, axis=1),
        ],
        axis=1,
    )


def _rows(v, sel):
    """The poses ``sel`` (N,) bool of ``exit_points``' value v: arrays with N rows, and the fields
    of its NamedTuples, taken; anything else kept."""
    if isinstance(v, tuple) and hasattr(v, "_fields"):
        return type(v)(*(_rows(f, sel) for f in v))
    if isinstance(v, np.ndarray) and v.shape[:1] == sel.shape:
        return v[sel]
    return v


def _jacobian_forces(G, Fi, r, rc, f):
    """d(F, M)/d(dp, dphi) (N, 6, 6) from each cable's force Fi (N, m, 3) at B_i and its derivative
    G_i = dF_i/dB_i (N, m, 3, 3) (``_jacobian`` with G_i given and t_i u_i = F_i)."""
    turn = r[..., :, None] * Fi[..., None, :] - np.einsum("nma,nma->nm", Fi, r)[..., None, None] * np.eye(3)
    return _assemble_jacobian(G, turn, r, rc, f)


def _jacobian(t, du, ka, u, dL, r, rc, f):
    """d(F, M)/d(dp, dphi) (N, 6, 6) of the force and moment balance (module docstring).

    With G_i = t_i du_i/dB + ka_i u_i dL_i^T and dB_i = dp - [r_i]x dphi:
    dF = sum G_i dB_i; dM = sum [r_i]x G_i dB_i + sum t_i (dphi x r_i) x u_i + (dphi x rc) x f, and
    (dphi x r) x u = (r u^T - (u . r) I) dphi."""
    G = t[..., None, None] * du + ka[..., None, None] * u[..., :, None] * dL[..., None, :]
    turn = t[..., None, None] * (
        r[..., :, None] * u[..., None, :] - np.einsum("nma,nma->nm", u, r)[..., None, None] * np.eye(3)
    )
    return _assemble_jacobian(G, turn, r, rc, f)


def _assemble_jacobian(G, turn, r, rc, f):
    """d(F, M)/d(dp, dphi) (N, 6, 6) from each cable's G_i = dF_i/dB_i (N, m, 3, 3) and its moment
    turn (dphi x r_i) x F_i = turn_i dphi (N, m, 3, 3) (``_jacobian``, ``_jacobian_forces``), with
    dB_i = dp - [r_i]x dphi and the weight f (3,) at rc (N, 3)."""
    Sr = skew(r)
    eye = np.eye(3)
    J = np.zeros(G.shape[:1] + (6, 6))
    J[:, :3, :3] = G.sum(axis=1)
    J[:, :3, 3:] = -np.einsum("nmab,nmbc->nac", G, Sr)
    RG = np.einsum("nmab,nmbc->nmac", Sr, G)
    J[:, 3:, :3] = RG.sum(axis=1)
    J[:, 3:, 3:] = -np.einsum("nmab,nmbc->nac", RG, Sr) + turn.sum(axis=1)
    J[:, 3:, 3:] += rc[:, :, None] * f[None, None, :] - (rc @ f)[:, None, None] * eye
    return J


def heavy_cables(cab, P, R, L0):
    """What each heavy cable does at the equilibria (``HeavyCables``; issue 38's per-cable keys):
    the tensions at B_i and D_i, H, the sag, the arc minus the chord, the angle of the force at B_i
    to the chord and the catenary status (``catenary.SPAN_STATUSES``).

    Parameters
    ----------
    cab : HeavyCables
        The robot's cables.
    P : ndarray (N, 3) [m]
        Platform positions.
    R : ndarray (N, 3, 3) [-]
        Platform orientations.
    L0 : ndarray (N, m) [m]
        Rest lengths of the whole cables.

    Returns
    -------
    dict
        t_B, t_D, H [N], sag, arc_minus_chord [m], angle_f_deg [deg], cable_status (str), all
        (N, m), sag_max (N,) [m], the exit points D (N, m, 3) [m], the wraps gamma (N, m) [rad],
        and the free span's V_B (N, m) [N] (the vertical force on the platform at B, up) and
        unstrained length L0_free (N, m) [m]: with H, what ``catenary.shape`` draws.

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2; Paty et al. 2021, eq. (10)-(13).
    """
    x = cab.exit_points(P, R, L0)
    l_h, l_v, st = x["l_h"], x["l_v"], x["state"]
    sp, a = st.span, (st.L0_free, cab.w, cab.EA)
    sag_ = sag(sp.H, sp.V_B, *a, l_h, l_v)
    return {
        "t_B": sp.T_B,
        "t_D": sp.T_D,
        "H": sp.H,
        "sag": sag_,
        "arc_minus_chord": arc_minus_chord(sp.H, sp.V_B, *a, l_h, l_v),
        "angle_f_deg": angle_f_deg(sp.H, sp.V_B, l_h, l_v),
        "cable_status": sp.status,
        "sag_max": sag_.max(axis=1),
        "D": x["D"],
        "gamma": x["gamma"],
        "V_B": sp.V_B,
        "L0_free": st.L0_free,
    }


def span_for_tension(l_h, l_v, T_B, w, EA, rtol=1e-15, maxiter=50):
    """The elastic catenary of given spans that carries the tension T_B at B (the heavy inverse of
    one span, issue 38): its end forces H = T_B cos psi, V_B = T_B sin psi and its unstrained
    length L0, the solution (psi, L0) of ``span_equations``(T_B cos psi, T_B sin psi, L0) =
    (l_h, l_v) by Newton's method with the analytic Jacobian

    .. math:: \\frac{\\partial(l_h, l_v)}{\\partial \\psi} = F\\,(-V_B, H), \\qquad
        \\frac{\\partial(l_h, l_v)}{\\partial L_0} = \\left(\\frac{1}{EA} + \\frac{1}{T_D}\\right)(H, V_D)

    (F the ``flexibility``; lengthening the span at D at fixed end forces at B adds an element
    along the stretched tangent at D), started from the straight Hooke spring along the chord
    (psi = atan2(l_v, l_h), L0 = chord / (1 + T_B/EA)), which is the answer at w = 0.

    Parameters
    ----------
    l_h : array_like (...) [m]
        Horizontal span from B to D (> 0).
    l_v : array_like (...) [m]
        Vertical span z_D - z_B.
    T_B : array_like (...) [N]
        Tension at B (> 0).
    w : array_like (...) [N/m]
        Weight per unstrained metre (>= 0).
    EA : array_like (...) [N]
        Axial stiffness (inf allowed).
    rtol : float
        Stop when the span residual is below rtol times the chord.
    maxiter : int
        Cap of Newton's iterations.

    Returns
    -------
    H, V_B : ndarray (...) [N]
        End forces on the platform at B (H toward D, V_B up).
    L0 : ndarray (...) [m]
        Unstrained length of the span.
    converged : ndarray (...) bool
        Newton reached the tolerance (False, and NaN outputs, where T_B <= 0 or l_h <= 0).
    iterations : ndarray (...) int
        Newton's iterations (0 at w = 0).

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    l_h, l_v, T, w, EA = (
        np.array(x)
        for x in np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (l_h, l_v, T_B, w, EA)))
    )
    shape = l_h.shape
    l_h, l_v, T, w, EA = (x.ravel() for x in (l_h, l_v, T, w, EA))
    c = np.hypot(l_h, l_v)
    ok = (T > 0.0) & (l_h > 0.0) & np.isfinite(T)
    psi = np.arctan2(l_v, l_h)
    with np.errstate(invalid="ignore"):
        L0 = c * np.where(np.isinf(EA), 1.0, EA / (EA + np.where(ok, T, 0.0)))
    it = np.zeros(l_h.size, dtype=np.int64)
    done = ~ok | (w == 0.0)
    for _ in range(maxiter):
        if done.all():
            break
        a = ~done
        H, V = T[a] * np.cos(psi[a]), T[a] * np.sin(psi[a])
        xh, xv = span_equations(H, V, L0[a], w[a], EA[a])
        rh, rv = xh - l_h[a], xv - l_v[a]
        small = np.hypot(rh, rv) <= rtol * c[a]
        F = flexibility(H, V, L0[a], w[a], EA[a])
        V_D = V + w[a] * L0[a]
        T_D = np.hypot(H, V_D)
        with np.errstate(divide="ignore", invalid="ignore"):  # the stretched tangent at D
            g = np.where(T_D > 0.0, 1.0 / EA[a] + 1.0 / T_D, 0.0)
        gh, gv = g * H, g * V_D
        j11 = -F[:, 0, 0] * V + F[:, 0, 1] * H
        j21 = -F[:, 1, 0] * V + F[:, 1, 1] * H
        det = j11 * gv - gh * j21
        with np.errstate(divide="ignore", invalid="ignore"):
            dpsi = -(gv * rh - gh * rv) / det
            dL = -(-j21 * rh + j11 * rv) / det
        dpsi = np.clip(np.where(np.isfinite(dpsi), dpsi, 0.0), -0.5, 0.5)
        dL = np.where(np.isfinite(dL), dL, 0.0)
        dL = np.maximum(dL, -0.5 * L0[a])
        idx = np.flatnonzero(a)
        step = ~small
        psi[idx[step]] += dpsi[step]
        L0[idx[step]] += dL[step]
        it[idx[step]] += 1
        done[idx[small]] = True
    conv = done & ok
    nan = np.where(conv, 1.0, np.nan)
    H, V = T * np.cos(psi) * nan, T * np.sin(psi) * nan
    return (
        H.reshape(shape),
        V.reshape(shape),
        (L0 * nan).reshape(shape),
        conv.reshape(shape),
        it.reshape(shape),
    )


def balance_jacobian(G, Fi, r, rc, f):
    """d(F, M)/d(dp, dφ) of the force and moment balance from each cable's force F_i at B_i and its
    derivative G_i = dF_i/dB_i (any cable model; the heavy sensitivities' exact G_i,
    ``heavy_sensitivity``).

    .. math:: dF = \\sum_i G_i\\,dB_i, \\quad dM = \\sum_i \\left(r_i \\times G_i\\,dB_i
        + (d\\varphi \\times r_i) \\times F_i\\right) + (d\\varphi \\times r_c) \\times f,
        \\quad dB_i = dp + d\\varphi \\times r_i

    Parameters
    ----------
    G : ndarray (N, m, 3, 3) [N/m]
        dF_i/dB_i.
    Fi : ndarray (N, m, 3) [N]
        Each cable's force on the platform at B_i.
    r : ndarray (N, m, 3) [m]
        r_i = R b_i.
    rc : ndarray (N, 3) [m]
        R c, the centre of mass from p.
    f : ndarray (3,) [N]
        The force acting at the centre of mass (the platform's weight).

    Returns
    -------
    J : ndarray (N, 6, 6) [N/m, N/rad, N m/m, N m/rad]
        Rows F, M; columns dp, dφ (φ a base-frame rotation vector).

    References
    ----------
    Paty et al. 2021, eq. (10)-(13) (the balance).
    """
    return _jacobian_forces(G, Fi, r, rc, f)
