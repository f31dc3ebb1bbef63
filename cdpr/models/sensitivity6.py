"""Sensitivities dp*/dθ and dφ*/dθ of a rigid platform's equilibrium (implicit-function theorem).

At the equilibrium x* = (p*, R*) under fixed commanded rest lengths L0 the force and moment
balance F6(x*, θ) = 0 holds (``equilibrium6``). Differentiating,

    dx*/dθ = -(dF6/dx)^-1 dF6/dθ,

with dF6/dx the solver's analytic 6 x 6 Jacobian (``equilibrium6._jacobian``; dφ a base-frame
rotation vector) and dF6/dθ the partial derivatives of the balance with respect to each parameter
at fixed pose, taken by central differences of the balance (the balance is evaluated, not solved,
so these are exact to O(δ²)). θ is the parameter vector of ``cdpr.parameters`` (E_i, h_i, r_p,i,
d_i, A_i) extended by the attachments b_i (platform frame), the centre of mass c and the mass M.

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

from cdpr.models.equilibrium6 import _Cables6, solve_spatial
from cdpr.models.sensitivity import COND_MAX, T_TOL


def parameter_names6(m):
    """Names of θ for a rigid platform on m cables (cables from 1).

    Parameters
    ----------
    m : int
        Number of cables.

    Returns
    -------
    names : list of str
        E_i, h_i, r_p_i, d_i, A_i_x/y/z, b_i_x/y/z for every cable, then c_x, c_y, c_z and M.
    """
    names = []
    for key in ("E", "h", "r_p", "d"):
        names += [f"{key}_{i + 1}" for i in range(m)]
    for key in ("A", "b"):
        names += [f"{key}_{i + 1}_{a}" for i in range(m) for a in "xyz"]
    return names + ["c_x", "c_y", "c_z", "M"]


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


def parameter_units6(m):
    """Units of the parameters of ``parameter_names6(m)`` (a sensitivity is in m or rad per unit).

    Parameters
    ----------
    m : int
        Number of cables.

    Returns
    -------
    units : list of str
        'Pa' for E_i, 'kg' for M, 'm' for every length and coordinate (h_i, r_p_i, d_i, A_i, b_i, c).
    """
    return ["Pa" if n.startswith("E_") else "kg" if n == "M" else "m" for n in parameter_names6(m)]


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
        d(F, M)/d(dp, dphi) (``equilibrium6._jacobian``).
    ell : float [m]
        The platform's size (``_Cables6.size``).
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
        cab = _Cables6(robot)
        cab.mass = robot.platform.mass
        cab.E = robot.arrays.E
        P, R, L0 = res["P_s"][idx], res["R_s"][idx], np.asarray(res["L0"])[idx]
        ev = cab.evaluate(P, R, L0, P)
        J = ev["J"]
        dF = np.empty((len(P), 6, len(names)))
        for k, name in enumerate(names):  # over the parameters, vectorised over the points
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
