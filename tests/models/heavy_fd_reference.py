"""The central-difference partials of the heavy balance that ``cdpr.models.heavy_sensitivity`` used
before its partials were analytic (issue 38): kept as the test reference of the analytic ones
(``heavy_partials``). Each is a central difference of the *balance* at fixed pose (``HeavyCables``,
each catenary solved by Newton to the last digits, the pulley coupling's fixed point to round-off), so
O(δ²) plus the balance's last digits over the step."""

import dataclasses

import numpy as np

from cdpr.models.cables import HeavyCables
from cdpr.models.platform import rotation_matrix

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


def _steps(robot, name, rel_step=REL_STEP):
    """(+ step, - step) of ``name``: relative for E_i, M (``rel_step``) and rho_i (``RHO_STEP``);
    STEP otherwise; a zero rho_i one-sided (step 1e-6 kg/m; 0 returned as the - step), a zero r_p_i too."""
    if name == "M":
        h = rel_step * robot.platform.mass
        return h, -h
    key, i = name.rsplit("_", 1)[0], name.rsplit("_", 1)[-1]
    if key == "E":
        h = rel_step * robot.cables[int(i) - 1].material.E
        return h, -h
    if key == "rho":
        rho = robot.cables[int(i) - 1].material.rho
        return (RHO_STEP * rho, -RHO_STEP * rho) if rho > 0 else (1e-6, 0.0)
    if key == "r_p" and robot.cables[int(i) - 1].pulley.r_p == 0.0:
        return STEP, 0.0  # a fixed pulley's zero radius: forward only (a negative radius means nothing)
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


def parameter_partials(robot, P, R, L0, names, rel_step=REL_STEP):
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
    f = robot.platform.w_ext
    per = [k for k, name in enumerate(names) if name != "M" and not name.startswith("c_")]
    if per and n:
        pn = [names[k] for k in per]
        hp, hm = np.array([_steps(robot, nm, rel_step) for nm in pn]).T
        zero = hm == 0.0  # one-sided (a zero density or radius): f(h), f(2 h) and the nominal cable
        hm = np.where(zero, 2.0 * hp, hm)
        big, ci = _expanded(robot, pn + pn, np.concatenate([hp, hm]))
        W = _cable_wrenches(HeavyCables(big), P, R, L0[:, np.concatenate([ci[: len(pn)], ci[: len(pn)]])])
        K = len(pn)
        up, dn = W[:, :K], W[:, K:]
        d = (up - dn) / (hp - hm)[None, :, None]
        if zero.any():  # second-order one-sided: (4 f(h) - f(2 h) - 3 f(0)) / (2 h)
            W0 = _cable_wrenches(HeavyCables(robot), P, R, L0)[:, ci[:K]]
            one = (4.0 * up - dn - 3.0 * W0) / (2.0 * hp)[None, :, None]
            d = np.where(zero[None, :, None], one, d)
        dF[:, :, per] = np.swapaxes(d, 1, 2)
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
