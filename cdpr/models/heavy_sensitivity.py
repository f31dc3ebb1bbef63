"""Pose sensitivities dp*/dθ and dφ*/dθ of a robot with heavy cables (issue 38), by the
implicit-function theorem on the heavy force and moment balance.

At the equilibrium x* = (p*, R*) under fixed commanded rest lengths L0, the balance of the
catenaries' end forces (``cables.HeavyCables``: Irvine's elastic catenary from B_i to the sheave
exit point D_i, with the pulley coupling) and the platform's weight vanishes, F6(x*, θ) = 0. So

    dx*/dθ = -(∂F6/∂x)^-1 ∂F6/∂θ,      dx*/dL0_i = -(∂F6/∂x)^-1 ∂F6/∂L0_i,

x = (p, φ), φ a base-frame rotation vector. Both partials are exact (``balance_partials``): each
cable's end force and its derivatives by B_i, its rest length and its own parameters come from the
implicit-function theorem on that cable's coupled system, the one ``HeavyCables`` solves by a fixed
point (the catenary's two span equations with the analytic flexibility matrix, the split of the rest
length between the free span and the dead part, and the exit point D_i on the sheave where the
catenary's end tangent touches it: ``heavy_partials``). So the exit point's slide on the sheave, the
swivel (any axis) and a DR arm's turn are all in ∂F6/∂x, the Jacobian of ``HeavyCables``' Newton
steps near the answer. θ is ``parameter_names(robot, rigid=True)``: E_i, h_i, r_p_i, d_i,
A_i, b_i, c, the linear densities rho_i [kg/m] and M. The central differences of the balance that
this module used before are the tests' reference (tests/models/heavy_fd_reference.py).

The compiled engine's heavy kernel solves the equilibrium but has no sensitivities: ``cdpr.solve``
routes every heavy-cable sensitivity here (numpy).

References
----------
Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263.
Implicit-function theorem, e.g. J. Nocedal and S. Wright, Numerical Optimization, 2nd ed.,
Springer 2006, A.2.
"""

from __future__ import annotations

import numpy as np

from cdpr.models.cables import HeavyCables, balance_jacobian
from cdpr.models.equilibrium import solve as solve_equilibrium
from cdpr.models.heavy_partials import cable_force_partials
from cdpr.models.results import ok_point_sensitivities
from cdpr.models.sensitivity import COND_MAX, T_TOL, pose_columns, scaled_condition
from cdpr.parameters import parameter_names


def balance_partials(robot, P, R, L0, names=None, cab=None):
    """The partial derivatives of the heavy balance F6 = (F, M) at fixed poses, exact: by the pose
    ∂F6/∂x, by the rest lengths ∂F6/∂L0_i and by the parameters ∂F6/∂θ (``heavy_partials``:
    the implicit-function theorem on each cable's coupled catenary, split and pulley coupling, the
    exit point's slide on the sheave included).

    With F_i the end force at B_i = p + R b_i, r_i = R b_i and G_i = dF_i/dB_i::

        ∂F6/∂x: ``cables.balance_jacobian`` (dB_i = dp - [r_i]x dφ),
        ∂F6/∂q_i = (dF_i/dq_i, r_i x dF_i/dq_i)  for q_i = L0_i, E_i (dEA = S_i dE), rho_i
            (dw = g U_i drho, U_i strands), h_i, r_p_i, d_i, A_i,
        ∂F6/∂b_i,a = (G_i R e_a, R e_a x F_i + r_i x G_i R e_a),
        ∂F6/∂c_a = (0, R e_a x f),  ∂F6/∂M = (f, R c x f) / M   (f the platform's weight).

    Parameters
    ----------
    robot : Robot
    P : ndarray (N, 3) [m]
        Platform positions.
    R : ndarray (N, 3, 3) [-]
        Orientations.
    L0 : ndarray (N, m) [m]
        Rest lengths of the whole cables.
    names : list of str, optional
        Parameters (``parameter_names(robot, rigid=True)`` or a subset; default all); another name
        raises CdprError (``sensitivity.pose_columns``).
    cab : HeavyCables, optional
        The robot's cables (default built from ``robot``).

    Returns
    -------
    dict
        J (N, 6, 6) [N/m, N/rad, N m/m, N m/rad]: ∂F6/∂x, x = (p, φ), φ a base-frame rotation
        vector; dL0 (N, 6, m) [N/m, N m/m]: ∂F6/∂L0_i; dtheta (N, 6, len(names)) [N, N m per unit of
        θ]; t (N, m) [N]: the tensions at B_i; names.

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2; Paty et al. 2021, eq. (3)-(7).
    """
    cab = HeavyCables(robot) if cab is None else cab
    names = pose_columns(robot, names)[0]  # an unknown name: one CdprError line
    P, R, L0 = (np.asarray(x, dtype=float) for x in (P, R, L0))
    cp = cable_force_partials(cab, P, R, L0)
    n, m = cp.t.shape
    a = robot.arrays
    f = cab.f
    weight = (
        robot.platform.gravity_force
    )  # M and c move the weight, not an external wrench (cab.f on a point mass)
    rc = R @ np.asarray(a.com, dtype=float)
    G = cp.dF[..., :3]
    J = balance_jacobian(G, cp.F, cp.r, rc, f)

    def wrench(dFi, r):  # (..., 3) -> (..., 6): the force and its moment r_i x dF_i
        return np.concatenate([dFi, np.cross(r, dFi)], axis=-1)

    dL0 = np.swapaxes(wrench(cp.dF[..., 3], cp.r), 1, 2)
    strands = np.array([c.strands for c in robot.cables], dtype=float)
    per = {
        "E": (4, a.ES / a.E),
        "rho": (5, robot.platform.g * strands),
        "h": (6, 1.0),
        "r_p": (7, 1.0),
        "d": (8, 1.0),
    }
    dth = np.zeros((n, 6, len(names)))
    for k, name in enumerate(names):
        parts = name.split("_")
        if name == "M":
            dth[:, :3, k] = weight / robot.platform.mass
            dth[:, 3:, k] = np.cross(rc, weight) / robot.platform.mass
        elif parts[0] == "c":
            dth[:, 3:, k] = np.cross(R[:, :, "xyz".index(parts[1])], weight)
        elif parts[0] in ("A", "b"):
            i, ax = int(parts[1]) - 1, "xyz".index(parts[2])
            if parts[0] == "A":
                dth[:, :, k] = wrench(cp.dF[:, i, :, 9 + ax], cp.r[:, i])
            else:
                e = R[:, :, ax]
                dFi = np.einsum("nab,nb->na", G[:, i], e)
                dth[:, :3, k] = dFi
                dth[:, 3:, k] = np.cross(e, cp.F[:, i]) + np.cross(cp.r[:, i], dFi)
        else:
            key, i = "_".join(parts[:-1]), int(parts[-1]) - 1
            col, scale = per[key]
            dFi = cp.dF[:, i, :, col] * np.broadcast_to(scale, (m,))[i]
            dth[:, :, k] = wrench(dFi, cp.r[:, i])
    return {"J": J, "dL0": dL0, "dtheta": dth, "t": cp.t, "names": names}


def pose_jacobian(robot, P, R, L0, cab=None):
    """∂F6/∂x (N, 6, 6) of the heavy balance at fixed rest lengths, exact (``balance_partials``),
    x = (p, φ) (φ a base-frame rotation vector: R <- exp([dφ]) R).

    Parameters
    ----------
    robot : Robot
    P : ndarray (N, 3) [m]
    R : ndarray (N, 3, 3) [-]
    L0 : ndarray (N, m) [m]
    cab : HeavyCables, optional
        The robot's cables (default built from ``robot``).

    Returns
    -------
    J : ndarray (N, 6, 6) [N/m, N/rad, N m/m, N m/rad]
    """
    return balance_partials(robot, P, R, L0, names=[], cab=cab)["J"]


def parameter_partials(robot, P, R, L0, names):
    """∂F6/∂θ (N, 6, len(names)) of the heavy balance at fixed poses and rest lengths, exact
    (``balance_partials``).

    Parameters
    ----------
    robot : Robot
    P : ndarray (N, 3) [m]
    R : ndarray (N, 3, 3) [-]
    L0 : ndarray (N, m) [m]
    names : list of str
        Parameters (``parameter_names(robot, rigid=True)`` or a subset).

    Returns
    -------
    dF : ndarray (N, 6, len(names)) [N, N m per unit of θ]
    """
    return balance_partials(robot, P, R, L0, names=names)["dtheta"]


def rest_length_partials(robot, P, R, L0, cab=None):
    """∂F6/∂L0_i (N, 6, m) of the heavy balance at fixed poses, exact (``balance_partials``).

    Parameters
    ----------
    robot : Robot
    P : ndarray (N, 3) [m]
    R : ndarray (N, 3, 3) [-]
    L0 : ndarray (N, m) [m]
    cab : HeavyCables, optional

    Returns
    -------
    dF : ndarray (N, 6, m) [N/m, N m/m]
    """
    return balance_partials(robot, P, R, L0, names=[], cab=cab)["dL0"]


def _solve_linear(J, dF, rigid):
    """-J^+ dF, the moment rows and rotation columns dropped on a point mass (its moment rows vanish)."""
    if not rigid:
        S = np.zeros(dF.shape)
        S[:, :3] = -np.linalg.solve(J[:, :3, :3], dF[:, :3])
        return S
    return -np.einsum("nab,nbk->nak", np.linalg.pinv(J, rcond=1e-12), dF)


def sensitivities_at(robot, res, names=None, t_tol=T_TOL):
    """dp*/dθ and dφ*/dθ at the equilibria of a heavy-cable ``solve`` result (module docstring):
    the heavy twin of ``sensitivity.sensitivities_at``, same keys.

    Parameters
    ----------
    robot : Robot
        The model at its nominal parameters (heavy cables).
    res : dict
        A physical-mode result (P_s (N, 3) [m], R_s (N, 3, 3), L0 (N, m) [m], status (N,)).
    names : list of str, optional
        Parameters (default ``parameter_names(robot, rigid=True)``, rho_1 .. rho_m among them).
    t_tol : float [N]
        Tension margin under which a point is not smooth.

    Returns
    -------
    dict
        names (n,); S (N, 6, n): rows dp_x, dp_y, dp_z [m per unit of θ] and dφ_x, dφ_y, dφ_z [rad
        per unit of θ], NaN where the status is not ok (dφ = 0 on a point mass); smooth (N,) bool:
        ok, every tension at B_i more than ``t_tol`` below T_a (and, on a massless cable, above 0)
        and ``scaled_condition`` below ``sensitivity.COND_MAX``; margin_t (N,) [N]; cond (N,).
    """
    names = parameter_names(robot, rigid=True) if names is None else list(names)

    def at(idx):
        cab = HeavyCables(robot)
        P, R, L0 = res["P_s"][idx], res["R_s"][idx], np.asarray(res["L0"], dtype=float)[idx]
        bp = balance_partials(robot, P, R, L0, names, cab)
        J, t = bp["J"], bp["t"]
        S = _solve_linear(J, bp["dtheta"], cab.rigid)
        low = np.where(robot.arrays.w > 0, np.inf, np.abs(t))
        margin = np.minimum(low.min(axis=1), (robot.T_a - t).min(axis=1))
        return S, margin, scaled_condition(J, cab.size, cab.rigid)

    return ok_point_sensitivities(res, names, at, t_tol, COND_MAX)


def pose_sensitivities(robot, p, rotvec=None, L0=None, names=None, t_tol=T_TOL, **solver):
    """The heavy equilibria under fixed rest lengths and their dp*/dθ, dφ*/dθ (``equilibrium.solve``
    then ``sensitivities_at``; the heavy twin of ``sensitivity.pose_sensitivities``).

    Parameters
    ----------
    robot : Robot
    p : array_like (N, 3) or (N, 6) [m, rad]
        Desired positions or poses.
    rotvec : array_like (N, 3) or (3,) [rad], optional
    L0 : array_like (N, m) [m], optional
        Commanded rest lengths, held fixed (default as ``equilibrium.solve``).
    names : list of str, optional
        Parameters (default ``parameter_names(robot, rigid=True)``).
    t_tol : float [N]
    solver : options of ``equilibrium.solve``.

    Returns
    -------
    dict
        The solve's result and names, S (N, 6, n), smooth, margin_t, cond (``sensitivities_at``).
    """
    res = solve_equilibrium(robot, p, rotvec, L0=L0, **solver)
    res.update(sensitivities_at(robot, res, names, t_tol))
    return res


def rest_length_sensitivities(robot, P, R, L0):
    """dx*/dL0 of the heavy equilibrium by the rest lengths (the heavy twin of
    ``sensitivity.rest_length_sensitivities``).

    Parameters
    ----------
    robot : Robot
    P : ndarray (n, 3) [m]
    R : ndarray (n, 3, 3) [-]
    L0 : ndarray (n, m) [m]

    Returns
    -------
    S : ndarray (n, 6, m) [m/m, rad/m]
    tension : ndarray (n, m) [N]
        The tensions at B_i (> 0 on a heavy cable).
    cond : ndarray (n,)
        Condition number of ∂F6/∂x (inf where singular; of its 3 x 3 block on a point mass).
    """
    cab = HeavyCables(robot)
    bp = balance_partials(robot, P, R, L0, names=[], cab=cab)
    J, t = bp["J"], bp["t"]
    S = _solve_linear(J, bp["dL0"], cab.rigid)
    with np.errstate(all="ignore"):
        cond = np.linalg.cond(J if cab.rigid else J[:, :3, :3])
    return S, t, np.where(np.isfinite(cond), cond, np.inf)
