"""Pose sensitivities dp*/dθ and dφ*/dθ of a robot with heavy cables (issue 38), by the
implicit-function theorem on the heavy force and moment balance.

At the equilibrium x* = (p*, R*) under fixed commanded rest lengths L0, the balance of the
catenaries' end forces (``cables.HeavyCables``: Irvine's elastic catenary from B_i to the sheave
exit point D_i, with the pulley coupling) and the platform's weight vanishes, F6(x*, θ) = 0. So

    dx*/dθ = -(∂F6/∂x)^-1 ∂F6/∂θ,      dx*/dL0_i = -(∂F6/∂x)^-1 ∂F6/∂L0_i,

x = (p, φ), φ a base-frame rotation vector. Both partials are taken at fixed pose by central
differences of the *balance* (``HeavyCables.evaluate``: each catenary solved by Newton on its two
span equations with the analytic flexibility matrix, to the last digits; the balance is evaluated,
not solved, so the partials are exact to O(δ²) as in the massless reference's ∂F6/∂θ,
``sensitivity.sensitivities_at``). ∂F6/∂x is differenced too: ``HeavyCables``' analytic Jacobian
leaves out the exit point's slide on the sheave (``HeavyCables`` docstring), which is right for
Newton's steps but not for a sensitivity. θ is ``parameter_names(robot, rigid=True)``: E_i, h_i,
r_p_i, d_i, A_i, b_i, c, the linear densities rho_i [kg/m] and M.

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

import dataclasses

import numpy as np

from cdpr.models.cables import HeavyCables
from cdpr.models.equilibrium import solve as solve_equilibrium
from cdpr.models.platform import rotation_matrix
from cdpr.models.results import ok_point_sensitivities
from cdpr.models.sensitivity import COND_MAX, T_TOL, scaled_condition
from cdpr.parameters import parameter_names

#: Central-difference step of a position or rotation [m, rad] (rest lengths and lengths too).
STEP = 1e-7
#: Relative step of E_i and M.
REL_STEP = 1e-6
#: Relative step of rho_i: its force change (w L δ) must stand well above the balance's last digits
#: (the pulley coupling's fixed point stops at 1e-15 m, times a cable stiffness of ~1e5 N/m).
RHO_STEP = 1e-4


def perturbed_robot(robot, name, delta):
    """``robot`` with the parameter ``name`` (``parameter_names(robot, rigid=True)``, plus rho_i)
    moved by ``delta`` (SI); the attachments b_i and the centre of mass c on a point mass too.

    Parameters
    ----------
    robot : Robot
    name : str
        E_i, h_i, r_p_i, d_i, A_i_x .. A_i_z, b_i_x .. b_i_z, c_x .. c_z, rho_i or M (cables from 1).
    delta : float
        The change [Pa, m, kg/m, kg].

    Returns
    -------
    Robot
    """
    parts = name.split("_")
    if name == "M":
        return dataclasses.replace(
            robot, platform=dataclasses.replace(robot.platform, mass=robot.platform.mass + delta)
        )
    if parts[0] == "c":
        com = list(robot.platform.com)
        com["xyz".index(parts[1])] += delta
        return dataclasses.replace(robot, platform=dataclasses.replace(robot.platform, com=tuple(com)))
    i = int(parts[1] if parts[0] in ("A", "b") else parts[-1]) - 1
    c = robot.cables[i]
    if parts[0] in ("A", "b"):
        key = "A" if parts[0] == "A" else "B"
        v = list(getattr(c, key))
        v["xyz".index(parts[2])] += delta
        c = dataclasses.replace(c, **{key: tuple(v)})
    else:
        key = "_".join(parts[:-1])
        if key == "E":
            c = dataclasses.replace(c, material=dataclasses.replace(c.material, E=c.material.E + delta))
        elif key == "rho":
            c = dataclasses.replace(c, material=dataclasses.replace(c.material, rho=c.material.rho + delta))
        elif key == "d":
            c = dataclasses.replace(c, dead_length=c.dead_length + delta)
        else:
            c = dataclasses.replace(
                c, pulley=dataclasses.replace(c.pulley, **{key: getattr(c.pulley, key) + delta})
            )
    cables = robot.cables[:i] + (c,) + robot.cables[i + 1 :]
    return dataclasses.replace(robot, cables=cables)


def _steps(robot, name):
    """(+ step, - step) of ``name``: relative for E_i, M (``REL_STEP``) and rho_i (``RHO_STEP``);
    STEP otherwise; a zero rho_i forward only, by 1e-6 kg/m (a negative density means nothing)."""
    if name == "M":
        h = REL_STEP * robot.platform.mass
        return h, -h
    key, i = name.rsplit("_", 1)[0], name.rsplit("_", 1)[-1]
    if key == "E":
        h = REL_STEP * robot.cables[int(i) - 1].material.E
        return h, -h
    if key == "rho":
        rho = robot.cables[int(i) - 1].material.rho
        return (RHO_STEP * rho, -RHO_STEP * rho) if rho > 0 else (1e-6, 0.0)
    return STEP, -STEP


def _wrench(cab, P, R, L0):
    """The balance F6 = (F, M) (N, 6) [N, N m] of ``HeavyCables`` ``cab`` at fixed poses."""
    ev = cab.evaluate(P, R, L0, P, jacobian=False)
    return np.concatenate([ev["F"], ev["M"]], axis=1)


def _cable_wrenches(cab, P, R, L0):
    """Each cable's wrench on the platform (N, m, 6) [N, N m]: the catenary's end force F_i at B_i
    and its moment r_i x F_i (``HeavyCables.exit_points``)."""
    x = cab.exit_points(P, R, L0)
    sp = x["state"].span
    Fi = sp.H[..., None] * x["e_h"] + sp.V_B[..., None] * cab.up
    return np.concatenate([Fi, np.cross(x["r"], Fi)], axis=-1)


def pose_jacobian(robot, P, R, L0, cab=None):
    """∂F6/∂x (N, 6, 6) of the heavy balance at fixed rest lengths, x = (p, φ) (φ a base-frame
    rotation vector: R ← exp([dφ]) R), by central differences of the balance (``STEP``), the 12
    perturbed poses of every point in one evaluation.

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
    cab = HeavyCables(robot) if cab is None else cab
    n = len(P)
    Ps, Rs = [], []
    for sg in (1.0, -1.0):
        for a in range(6):
            e = np.zeros(3)
            e[a % 3] = sg * STEP
            Ps.append(P + e if a < 3 else P)
            Rs.append(R if a < 3 else rotation_matrix(e) @ R)
    W = _wrench(cab, np.concatenate(Ps), np.concatenate(Rs), np.tile(L0, (12, 1))).reshape(2, 6, n, 6)
    return np.transpose(W[0] - W[1], (1, 2, 0)) / (2 * STEP)


def _expanded(robot, names, steps):
    """A robot whose cables are cable c_k of ``robot`` with parameter ``names[k]`` moved by
    ``steps[k]``, one per (name, step), and the cable index c_k of each."""
    cables, ci = [], []
    for name, h in zip(names, steps):
        parts = name.split("_")
        i = int(parts[1] if parts[0] in ("A", "b") else parts[-1]) - 1
        cables.append(perturbed_robot(robot, name, h).cables[i])
        ci.append(i)
    return dataclasses.replace(robot, cables=tuple(cables)), np.array(ci, dtype=np.intp)


def parameter_partials(robot, P, R, L0, names):
    """∂F6/∂θ (N, 6, len(names)) of the heavy balance at fixed poses and rest lengths.

    Parameters of one cable (E_i, h_i, r_p_i, d_i, A_i, b_i, rho_i): central differences of that
    cable's wrench alone (the others cancel), every perturbed cable one column of a single
    evaluation of the catenaries and pulleys (``_expanded``; steps ``_steps``). The centre of mass
    and the mass enter the balance in closed form: ∂M/∂c = (R e_a) x f, ∂(F, M)/∂M = (f, (R c) x f) / M
    with f the platform's weight.

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
    n = len(P)
    dF = np.zeros((n, 6, len(names)))
    f = robot.platform.gravity_force  # the weight: an external wrench (Platform.wrench) has no parameter
    per = [k for k, name in enumerate(names) if name != "M" and not name.startswith("c_")]
    if per and n:
        pn = [names[k] for k in per]
        hp, hm = np.array([_steps(robot, nm) for nm in pn]).T
        big, ci = _expanded(robot, pn + pn, np.concatenate([hp, hm]))
        W = _cable_wrenches(HeavyCables(big), P, R, L0[:, np.concatenate([ci[: len(pn)], ci[: len(pn)]])])
        K = len(pn)
        up, dn = W[:, :K], W[:, K:]
        zero = hm == 0.0  # forward differences from the nominal cable (a zero density)
        if zero.any():
            W0 = _cable_wrenches(HeavyCables(robot), P, R, L0)
            dn = np.where(zero[None, :, None], W0[:, ci[:K]], dn)
        dF[:, :, per] = np.swapaxes((up - dn) / (hp - hm)[None, :, None], 1, 2)
    for k, name in enumerate(names):
        if name == "M":
            rc = R @ np.asarray(robot.platform.com, dtype=float)
            dF[:, :3, k] = f / robot.platform.mass
            dF[:, 3:, k] = np.cross(rc, f) / robot.platform.mass
        elif name.startswith("c_"):
            dF[:, 3:, k] = np.cross(R[:, :, "xyz".index(name[2])], f)
    return dF


def rest_length_partials(robot, P, R, L0, cab=None):
    """∂F6/∂L0_i (N, 6, m) of the heavy balance at fixed poses: central differences (``STEP``) of
    each cable's own wrench (every cable's rest length moved at once, each wrench depending on its own).

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
    cab = HeavyCables(robot) if cab is None else cab
    up = _cable_wrenches(cab, P, R, L0 + STEP)
    dn = _cable_wrenches(cab, P, R, L0 - STEP)
    return np.swapaxes(up - dn, 1, 2) / (2 * STEP)


def _solve_linear(J, dF, rigid):
    """-J^+ dF, the moment rows and rotation columns dropped on a point mass (its moment rows vanish)."""
    if not rigid:
        S = np.zeros(dF.shape)
        S[:, :3] = -np.linalg.solve(J[:, :3, :3], dF[:, :3])
        return S
    return -np.einsum("nab,nbk->nak", np.linalg.pinv(J, rcond=1e-12), dF)


def _linear_response(robot, P, R, L0, cab, dF):
    """∂F6/∂x (``pose_jacobian``), the response -(∂F6/∂x)^+ dF (``_solve_linear``) and the tensions
    at B_i of the heavy balance at fixed poses, for the partials dF (N, 6, k) of F6."""
    J = pose_jacobian(robot, P, R, L0, cab)
    S = _solve_linear(J, dF, cab.rigid)
    return J, S, cab.evaluate(P, R, L0, P, jacobian=False)["t"]


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
        J, S, t = _linear_response(robot, P, R, L0, cab, parameter_partials(robot, P, R, L0, names))
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
    L0 = np.asarray(L0, dtype=float)
    J, S, t = _linear_response(robot, P, R, L0, cab, rest_length_partials(robot, P, R, L0, cab))
    with np.errstate(all="ignore"):
        cond = np.linalg.cond(J if cab.rigid else J[:, :3, :3])
    return S, t, np.where(np.isfinite(cond), cond, np.inf)
