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


def spatial_sensitivities(robot, p, rotvec=None, L0=None, names=None):
    """dp*/dθ and dφ*/dθ at the equilibria under fixed commanded rest lengths.

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

    Returns
    -------
    dict
        The ``solve_spatial`` result and names (n,), S (N, 6, n): rows dp_x, dp_y, dp_z [m per
        unit of θ] and dφ_x, dφ_y, dφ_z [rad per unit of θ] (base-frame rotation vector).

    References
    ----------
    Paty et al. 2021 (parameters); implicit-function theorem on Pott 2018's elastic equilibrium.
    """
    res = solve_spatial(robot, p, rotvec, L0=L0)
    names = parameter_names6(robot.m) if names is None else list(names)
    cab = _Cables6(robot)
    cab.mass = robot.platform.mass
    cab.E = robot.arrays.E
    P, R, L0 = res["P_s"], res["R_s"], res["L0"]
    ev = cab.evaluate(P, R, L0, P)
    J = ev["J"]
    dF = np.empty((len(P), 6, len(names)))
    for k, name in enumerate(names):
        h = _step(name, cab)
        up = _perturbed(cab, name, h).evaluate(P, R, L0, P, jacobian=False)
        dn = _perturbed(cab, name, -h).evaluate(P, R, L0, P, jacobian=False)
        dF[:, :3, k] = (up["F"] - dn["F"]) / (2 * h)
        dF[:, 3:, k] = (up["M"] - dn["M"]) / (2 * h)
    if not cab.rigid:
        dF[:, 3:] = 0.0
    S = -np.einsum("nab,nbk->nak", np.linalg.pinv(J, rcond=1e-12), dF)
    res.update(names=names, S=S)
    return res
