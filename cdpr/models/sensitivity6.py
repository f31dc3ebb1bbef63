"""Sensitivities dp*/dθ and dφ*/dθ of a rigid platform's equilibrium (implicit-function theorem).

At the equilibrium x* = (p*, R*) under fixed commanded rest lengths L0 the force and moment
balance F6(x*, θ) = 0 holds (``equilibrium``). Differentiating,

    dx*/dθ = -(dF6/dx)^-1 dF6/dθ,

with dF6/dx the solver's analytic 6 x 6 Jacobian (``equilibrium._jacobian``; dφ a base-frame
rotation vector) and dF6/dθ the partial derivatives of the balance with respect to each parameter
at fixed pose, taken by central differences of the balance (the balance is evaluated, not solved,
so these are exact to O(δ²)). θ is the spatial parameter vector of ``cdpr.parameters``
(``parameter_names6``: E_i, h_i, r_p,i, d_i, A_i, the attachments b_i (platform frame), the centre
of mass c and the mass M).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (the parameters).

Pott, A. (2018). Cable-Driven Parallel Robots: Theory and Application. Springer, ch. 3 (stiffness
of the elastic equilibrium).
"""

from __future__ import annotations

import copy

import numpy as np

from cdpr.models.equilibrium import Cables
from cdpr.models.equilibrium import solve as solve_spatial
from cdpr.models.pulleys import total_length_and_direction
from cdpr.models.sensitivity import COND_MAX, T_TOL
from cdpr.models.statics import length_gradient
from cdpr.parameters import parameter_names6, parameter_units6

__all__ = [
    "parameter_names6",
    "parameter_units6",
    "rest_length_sensitivities",
    "scaled_condition",
    "sensitivities_at",
    "sensitivity_columns6",
    "spatial_sensitivities",
    "tension_partials6",
]


def _perturbed(cab, name, delta):
    """A copy of the cables' evaluator with parameter ``name`` moved by ``delta`` (SI)."""
    c = copy.copy(cab)
    A, kind, h, r_p, d, inward, frame = cab.args
    parts = name.split("_")
    if name == "M":
        c.f = cab.f * (1.0 + delta / cab.mass)
    elif parts[0] == "c":
        com = cab.com.copy()
        com["xyz".index(parts[1])] += delta
        c.com = com
    elif parts[0] in ("A", "b"):
        i, a = int(parts[1]) - 1, "xyz".index(parts[2])
        arr = (A if parts[0] == "A" else cab.b).copy()
        arr[i, a] += delta
        if parts[0] == "A":
            c.args = (arr, kind, h, r_p, d, inward, frame)
        else:
            c.b = arr
    else:
        key, i = "_".join(parts[:-1]), int(parts[-1]) - 1
        if key == "E":
            ES = cab.ES.copy()
            ES[i] *= 1.0 + delta / cab.E[i]
            c.ES = ES
        else:
            vals = {"h": h, "r_p": r_p, "d": d}
            arr = vals[key].copy()
            arr[i] += delta
            vals[key] = arr
            c.args = (A, kind, vals["h"], vals["r_p"], vals["d"], inward, frame)
    return c


def _step(name, cab):
    """Central-difference step for parameter ``name`` (relative for E and M, 1e-7 m otherwise)."""
    if name == "M":
        return 1e-6 * cab.mass
    if name.startswith("E_"):
        return 1e-6 * cab.E[int(name.split("_")[1]) - 1]
    return 1e-7


def _perturbed_tensions(cab, names, P, R, L0):
    """Every parameter of ``names`` that belongs to one cable (E_i, h_i, r_p_i, d_i, A_i_xyz,
    b_i_xyz) moved by + and - its step (``_step``), each perturbed cable one column of a single
    evaluation of the pulley model at fixed poses: tensions t (N, 2K) [N], directions u (N, 2K, 3)
    and lever arms r = R b (N, 2K, 3) [m] (columns 0..K-1 the + steps, K..2K-1 the - steps), the
    steps (K,) and the cable of each parameter (K,) (0-based)."""
    A, kind, h, r_p, d, inward, frame = cab.args
    ci, steps = [], []
    for name in names:
        parts = name.split("_")
        ci.append(int(parts[1] if parts[0] in ("A", "b") else parts[-1]) - 1)
        steps.append(_step(name, cab))
    ci, steps = np.array(ci, dtype=int), np.array(steps)
    K = len(names)
    c2 = np.concatenate([ci, ci])
    A2, b2 = A[c2].copy(), cab.b[c2].copy()
    h2, r2, d2, ES2 = h[c2].copy(), r_p[c2].copy(), d[c2].copy(), cab.ES[c2].copy()
    for j, name in enumerate(names):
        parts = name.split("_")
        for col, sg in ((j, 1.0), (K + j, -1.0)):
            delta = sg * steps[j]
            if parts[0] in ("A", "b"):
                (A2 if parts[0] == "A" else b2)[col, "xyz".index(parts[2])] += delta
            elif parts[0] == "E":
                ES2[col] *= 1.0 + delta / cab.E[ci[j]]
            else:
                {"h": h2, "r_p": r2, "d": d2}["_".join(parts[:-1])][col] += delta
    r = np.einsum("nab,mb->nma", R, b2)
    g = total_length_and_direction(
        P[:, None, :] + r,
        A2,
        kind[c2],
        h2,
        r2,
        d2,
        inward[c2],
        None if frame is None else frame[c2],
        per_cable=True,
    )
    L0c = L0[:, c2]
    e = g.L_TE - L0c
    t = np.where(e > 0.0, ES2 / L0c * e, 0.0)
    return t, g.u, r, steps, ci


def _cable_partials(cab, names, P, R, L0):
    """dF6/dθ (N, 6, len(names)) at fixed poses of parameters that belong to one cable (E_i, h_i,
    r_p_i, d_i, A_i_xyz, b_i_xyz), by central differences of that cable's wrench alone
    (``_perturbed_tensions``: the other cables' wrenches cancel in the difference)."""
    t, u, r, steps, _ = _perturbed_tensions(cab, names, P, R, L0)
    K = len(names)
    f = t[..., None] * u
    mom = t[..., None] * np.cross(r, u)
    out = np.empty((len(P), 6, K))
    out[:, :3] = np.swapaxes(f[:, :K] - f[:, K:], 1, 2) / (2 * steps)
    out[:, 3:] = np.swapaxes(mom[:, :K] - mom[:, K:], 1, 2) / (2 * steps)
    return out


def tension_partials6(robot, P, R, L0, names=None):
    r"""The cable tensions at fixed poses of a rigid platform and their partial derivatives by the
    pose, the rest lengths and the parameters.

    .. math:: t_i = a_i k_i (L_{TE,i}(B_i) - L0_i),\quad k_i = \frac{E_i S_i}{L0_i},\quad
              B_i = p + R b_i,

    .. math:: \frac{\partial t_i}{\partial (p, \varphi)} = a_i k_i
              \left[\frac{\partial L_{TE,i}}{\partial B},\;
              r_i \times \frac{\partial L_{TE,i}}{\partial B}\right],\quad
              \frac{\partial t_i}{\partial L0_i} = -a_i k_i \frac{L_{TE,i}}{L0_i}

    (dB_i = dp + dφ × r_i, r_i = R b_i, φ a base-frame rotation vector; a_i = 1 on a taut cable,
    L_TE,i ≥ L0_i); ∂t_i/∂θ at fixed pose and rest lengths by central differences of that cable's
    tension alone (``_perturbed_tensions``, the steps of the wrench partials: exact to O(δ²)) for
    E_i, h_i, r_p_i, d_i, A_i, b_i, and 0 for the centre of mass and the mass (they move the
    tensions only through the pose).

    Parameters
    ----------
    robot : Robot
    P : ndarray, shape (n, 3) [m]
        Platform positions.
    R : ndarray, shape (n, 3, 3) [-]
        Orientations.
    L0 : ndarray, shape (n, m) [m]
        Rest lengths.
    names : list of str, optional
        Parameters (``parameter_names6``; default all).

    Returns
    -------
    dict
        t (n, m) [N] (0 on a slack cable); dt_dx (n, m, 6) [N/m, N/rad]; dt_dL0 (n, m) [N/m]
        (cable i's own rest length); dt_dtheta (n, m, len(names)) [N per unit of θ].

    References
    ----------
    Paty et al. 2021, eq. (5), (10), (13) (the total length and Hooke's law at B_i).
    """
    names = parameter_names6(robot.m) if names is None else list(names)
    cab = Cables(robot)
    cab.mass = robot.platform.mass
    cab.E = robot.arrays.E
    r = np.einsum("nab,mb->nma", R, cab.b)
    g = total_length_and_direction(P[:, None, :] + r, *cab.args, per_cable=True)
    k = cab.ES / L0
    e = g.L_TE - L0
    ka = k * (e >= 0.0)
    dL = length_gradient(g)
    n = len(P)
    out = {
        "t": ka * e,
        "dt_dx": ka[..., None] * np.concatenate([dL, np.cross(r, dL)], axis=-1),
        "dt_dL0": -ka * g.L_TE / L0,
        "dt_dtheta": np.zeros((n, robot.m, len(names))),
    }
    per = [j for j, name in enumerate(names) if name != "M" and not name.startswith("c_")]
    if per and n:
        t, _, _, steps, ci = _perturbed_tensions(cab, [names[j] for j in per], P, R, L0)
        K = len(per)
        out["dt_dtheta"][:, ci, per] = (t[:, :K] - t[:, K:]) / (2 * steps)
    return out


def sensitivity_columns6(names):
    """Table column names of the 6-DoF sensitivities: dx_d<name>, dy_d<name>, dz_d<name> [m per
    unit] then dphix_d<name>, dphiy_d<name>, dphiz_d<name> [rad per unit] per parameter.

    Parameters
    ----------
    names : list of str
        ``parameter_names6``.

    Returns
    -------
    columns : list of str, length 6 len(names)
    """
    return [f"d{ax}_d{nm}" for nm in names for ax in ("x", "y", "z", "phix", "phiy", "phiz")]


def scaled_condition(J, ell, rigid=True):
    """Condition number ||J_s||_F ||J_s^-1||_F of the balance's Jacobian in consistent units,
    J_s = D^-1 J D^-1 with D = diag(1, 1, 1, ell, ell, ell) (moments per ell, rotations times ell:
    every entry in N/m); the 3 x 3 translation block for a platform without moments (``rigid``
    False). inf where J is singular or not finite.

    Parameters
    ----------
    J : ndarray (N, 6, 6) [N/m, N/rad, N m/m, N m/rad]
        d(F, M)/d(dp, dphi) (``equilibrium._jacobian``).
    ell : float [m]
        The platform's size (``Cables.size``).
    rigid : bool
        Whether the moment rows count.

    Returns
    -------
    cond : ndarray (N,) [-]
    """
    D = np.array([1.0, 1.0, 1.0, ell, ell, ell])
    Js = J / D[:, None] / D[None, :]
    if not rigid:
        Js = Js[:, :3, :3]
    cond = np.full(len(J), np.inf)
    ok = np.isfinite(Js).all(axis=(1, 2))
    if ok.any():
        s = np.linalg.svd(Js[ok], compute_uv=False)
        with np.errstate(divide="ignore"):
            c = np.sqrt((s**2).sum(axis=1)) * np.sqrt((1.0 / s**2).sum(axis=1))
        cond[ok] = np.where(s[:, -1] > 0, c, np.inf)
    return cond


def sensitivities_at(robot, res, names=None, t_tol=T_TOL):
    """dp*/dθ and dφ*/dθ at the equilibria of a ``solve_spatial`` result (implicit-function theorem),
    with the smoothness flag of the point-mass physical mode.

    .. math:: \\frac{dx^*}{d\\theta} = -\\left(\\frac{\\partial F_6}{\\partial x}\\right)^{+}
        \\frac{\\partial F_6}{\\partial \\theta}, \\qquad x = (\\mathbf p, \\boldsymbol\\varphi)

    Parameters
    ----------
    robot : Robot
        The model at its nominal parameters.
    res : dict
        A ``solve_spatial`` result (P_s (N, 3) [m], R_s (N, 3, 3), L0 (N, m) [m], status (N,)), from
        either engine.
    names : list of str, optional
        Parameters (default ``parameter_names6(m)``).
    t_tol : float [N]
        Tension margin under which a point is not smooth (``sensitivity.T_TOL``).

    Returns
    -------
    dict
        names (n,); S (N, 6, n): rows dp_x, dp_y, dp_z [m per unit of θ] and dφ_x, dφ_y, dφ_z [rad
        per unit of θ] (base-frame rotation vector), NaN where the status is not ok; smooth (N,)
        bool: ok, every cable's Hooke tension (E_i S_i/L0_i)(L_TE,i - L0_i) (the would-be one of a
        slack cable) more than ``t_tol`` from 0 and from T_a (the taut set is not about to change)
        and ``scaled_condition`` below ``sensitivity.COND_MAX`` (the Jacobian is not singular), as
        ``sensitivity.sensitivities`` decides it for a point mass; margin_t (N,) [N]; cond (N,).

    References
    ----------
    Paty et al. 2021 (parameters); implicit-function theorem on Pott 2018's elastic equilibrium.
    """
    names = parameter_names6(robot.m) if names is None else list(names)
    n = len(res["P_s"])
    S = np.full((n, 6, len(names)), np.nan)
    margin = np.full(n, np.nan)
    cond = np.full(n, np.inf)
    ok = np.asarray(res["status"]) == "ok"
    idx = np.flatnonzero(ok)
    if idx.size:
        cab = Cables(robot)
        cab.mass = robot.platform.mass
        cab.E = robot.arrays.E
        P, R, L0 = res["P_s"][idx], res["R_s"][idx], np.asarray(res["L0"])[idx]
        ev = cab.evaluate(P, R, L0, P)
        J = ev["J"]
        dF = np.empty((len(P), 6, len(names)))
        per = [k for k, name in enumerate(names) if name != "M" and not name.startswith("c_")]
        if per:  # every per-cable parameter in one evaluation of the pulley model
            dF[:, :, per] = _cable_partials(cab, [names[k] for k in per], P, R, L0)
        for k, name in enumerate(names):  # c and M, vectorised over the points
            if k in per:
                continue
            h = _step(name, cab)
            up = _perturbed(cab, name, h).evaluate(P, R, L0, P, jacobian=False)
            dn = _perturbed(cab, name, -h).evaluate(P, R, L0, P, jacobian=False)
            dF[:, :3, k] = (up["F"] - dn["F"]) / (2 * h)
            dF[:, 3:, k] = (up["M"] - dn["M"]) / (2 * h)
        if not cab.rigid:
            dF[:, 3:] = 0.0
        S[idx] = -np.einsum("nab,nbk->nak", np.linalg.pinv(J, rcond=1e-12), dF)
        hooke = cab.ES / L0 * (ev["g"].L_TE - L0)
        over = np.where(hooke > 0, robot.T_a - hooke, np.inf)
        margin[idx] = np.minimum(np.abs(hooke).min(axis=1), over.min(axis=1))
        cond[idx] = scaled_condition(J, cab.size, cab.rigid)
    smooth = ok & (margin > t_tol) & (cond < COND_MAX)
    return {"names": names, "S": S, "smooth": smooth, "margin_t": margin, "cond": cond}


def spatial_sensitivities(robot, p, rotvec=None, L0=None, names=None, t_tol=T_TOL, **solver):
    """dp*/dθ and dφ*/dθ at the equilibria under fixed commanded rest lengths (the numpy reference:
    ``solve_spatial`` then ``sensitivities_at``).

    Parameters
    ----------
    robot : Robot
    p : array_like (N, 3) or (N, 6) [m, rad]
        Desired positions or poses.
    rotvec : array_like (N, 3) or (3,) [rad], optional
        Desired orientations.
    L0 : array_like (N, m) [m], optional
        Commanded rest lengths (default L_TS at the desired pose), held fixed.
    names : list of str, optional
        Parameters (default ``parameter_names6(m)``).
    t_tol : float [N]
        Tension margin of the smoothness flag (``sensitivities_at``).
    solver : options of ``solve_spatial`` (tol, maxiter, max_step, restarts, P0).

    Returns
    -------
    dict
        The ``solve_spatial`` result and names (n,), S (N, 6, n): rows dp_x, dp_y, dp_z [m per
        unit of θ] and dφ_x, dφ_y, dφ_z [rad per unit of θ] (base-frame rotation vector), NaN where
        the status is not ok; smooth (N,), margin_t (N,) [N], cond (N,) (``sensitivities_at``).

    References
    ----------
    Paty et al. 2021 (parameters); implicit-function theorem on Pott 2018's elastic equilibrium.
    """
    res = solve_spatial(robot, p, rotvec, L0=L0, **solver)
    res.update(sensitivities_at(robot, res, names, t_tol))
    return res


def rest_length_sensitivities(robot, P, R, L0):
    r"""dx*/dL0 of the equilibrium pose by the commanded rest lengths, and the Hooke tensions.

    .. math:: \frac{dx^*}{dL0_i} = -\left(\frac{dF_6}{dx}\right)^{-1}
              \frac{\partial F_6}{\partial L0_i},\quad
              \frac{\partial F_6}{\partial L0_i} = -a_i \frac{E_i S_i}{L0_i}
              \frac{L_{TE,i}}{L0_i} \begin{bmatrix} u_i \\ r_i \times u_i \end{bmatrix}

    (t_i = E_i S_i (L_TE,i - L0_i) / L0_i, a_i = 1 on a taut cable, r_i = R b_i); x = (p, φ), φ a
    base-frame rotation vector.

    Parameters
    ----------
    robot : Robot
    P : ndarray, shape (n, 3) [m]
        Equilibrium positions.
    R : ndarray, shape (n, 3, 3) [-]
        Equilibrium orientations.
    L0 : ndarray, shape (n, m) [m]
        Rest lengths.

    Returns
    -------
    S : ndarray, shape (n, 6, m) [m/m, rad/m]
        Rows dp_x, dp_y, dp_z, dφ_x, dφ_y, dφ_z.
    hooke : ndarray, shape (n, m) [N]
        k_i (L_TE,i - L0_i), negative on a slack cable (its distance to becoming taut).
    cond : ndarray, shape (n,)
        Condition number of dF6/dx (inf where singular).

    References
    ----------
    Paty et al. 2021, eq. (10)-(13); implicit-function theorem.
    """
    cab = Cables(robot)
    ev = cab.evaluate(P, R, L0, P)
    g = ev["g"]
    k = cab.ES / L0
    e = g.L_TE - L0
    r = np.einsum("nab,mb->nma", R, cab.b)
    w = -((e >= 0) * k * g.L_TE / L0)  # (n, m)
    dF = np.concatenate(
        [w[:, None, :] * np.swapaxes(g.u, 1, 2), w[:, None, :] * np.swapaxes(np.cross(r, g.u), 1, 2)], axis=1
    )
    J = ev["J"]
    S = -np.einsum("nab,nbk->nak", np.linalg.pinv(J, rcond=1e-12), dF)
    with np.errstate(all="ignore"):
        cond = np.linalg.cond(J)
    return S, k * e, np.where(np.isfinite(cond), cond, np.inf)
