"""The interference-free workspace of a grid at a fixed orientation: the share, volume and
largest axis-aligned box of the cell-centred grid's poses at which no two cables touch and no cable
runs through the platform (``cdpr.models.interference``), and, if asked, its intersection with the
wrench-feasible workspace (``tension_distribution.distribute_pose``).

The poses are the desired poses of the grid, not solved equilibria (the workspace of the design,
as the wrench-feasible workspace of ``cdpr grid --wrench-feasible``).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (section 4.1.1: the
regular workspace as the largest box of admissible voxels).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from cdpr.analyses.compensation import compensate
from cdpr.analyses.workspace import cell_centres, check_box, largest_box
from cdpr.errors import CdprError
from cdpr.models.interference import COLUMNS, columns, interference
from cdpr.models.inverse import L_TS
from cdpr.models.platform import pose_arrays
from cdpr.models.tension_distribution import T_MIN_DEFAULT, distribute_pose
from cdpr.solve import heavy_cables_at


def grid_of(box, shape):
    """The cell-centred (nx, ny, nz) grid of ``box`` in C order (x slowest, z fastest).

    Parameters
    ----------
    box : sequence of 6 float [m]
        xmin, xmax, ymin, ymax, zmin, zmax.
    shape : int or sequence of 3 int
        Cells per axis (one int: the same on every axis).

    Returns
    -------
    points : ndarray (nx ny nz, 3) [m]
    shape : tuple of 3 int
    """
    b = check_box(box)
    shape = (int(shape),) * 3 if np.isscalar(shape) else tuple(int(n) for n in shape)
    if len(shape) != 3 or min(shape) < 1:
        raise CdprError(f"a grid needs three counts of cells >= 1, got {shape}")
    axes = [cell_centres(b[2 * a], b[2 * a + 1], shape[a]) for a in range(3)]
    X, Y, Z = np.meshgrid(*axes, indexing="ij")
    return np.column_stack([X.ravel(), Y.ravel(), Z.ravel()]), shape


def _box_of(mask, box, shape):
    """The largest box of True voxels of ``mask`` (``workspace.largest_box``): count, bounds [m]
    (the cells' outer faces, or None) and volume [m^3]."""
    b = check_box(box)
    step = (b[1::2] - b[0::2]) / np.asarray(shape)
    count, cells = largest_box(mask.reshape(shape))
    if cells is None:
        return 0, None, 0.0
    bounds = []
    for a in range(3):
        bounds += [
            float(b[2 * a] + cells[2 * a] * step[a]),
            float(b[2 * a] + (cells[2 * a + 1] + 1) * step[a]),
        ]
    return int(count), bounds, float(count * np.prod(step))


def interference_workspace(robot, box, shape, rotvec=None, wrench_feasible=False, t_min=T_MIN_DEFAULT):
    """Interference-free workspace of the cell-centred grid of ``box`` at one orientation.

    A voxel counts when its centre pose is free of interference (``models.interference``);
    volumes are voxel counts times the voxel's volume, the box is the largest axis-aligned box of
    counted voxels (Paty 2021 section 4.1.1's search, ``workspace.largest_box``).

    Parameters
    ----------
    robot : Robot
    box : sequence of 6 float [m]
        The grid's box (e.g. ``workspace.frame_box(robot)``).
    shape : int or sequence of 3 int
        Cells per axis.
    rotvec : array_like (3,) [rad], optional
        The fixed orientation (default identity).
    wrench_feasible : bool
        Also intersect with the wrench-feasible workspace (a tension distribution in
        [t_min, T_a] holds the platform at the pose).
    t_min : float [N]
        Least tension of the wrench feasibility.

    Returns
    -------
    dict
        points; free_points, fraction (free share), volume_m3, box (6 float [m] or None), box_m3;
        cc_points and cp_points (poses with a cable-cable, a cable-platform interference); with
        ``wrench_feasible`` also feasible_points, free_feasible_points, free_feasible_m3,
        free_feasible_box and free_feasible_box_m3; and the per-voxel masks free (and feasible),
        arrays (N,) bool in C order.
    """
    P, shape = grid_of(box, shape)
    rv = np.zeros(3) if rotvec is None else np.asarray(rotvec, dtype=float)
    res = interference(robot, P, rv)
    voxel = float(np.prod((check_box(box)[1::2] - check_box(box)[0::2]) / np.asarray(shape)))
    count, bounds, box_m3 = _box_of(res.free, box, shape)
    out = {
        "points": len(P),
        "free_points": int(res.free.sum()),
        "fraction": float(res.free.mean()),
        "volume_m3": float(res.free.sum() * voxel),
        "box": bounds,
        "box_m3": box_m3,
        "cc_points": int(res.cc.any(axis=1).sum()),
        "cp_points": int(res.cp.any(axis=1).sum()),
        "free": res.free,
    }
    if wrench_feasible:
        feasible = np.asarray(distribute_pose(robot, P, rv, t_min=t_min)["feasible"], dtype=bool)
        both = feasible & res.free
        _, fb, fb_m3 = _box_of(both, box, shape)
        out.update(
            feasible_points=int(feasible.sum()),
            free_feasible_points=int(both.sum()),
            free_feasible_m3=float(both.sum() * voxel),
            free_feasible_box=fb,
            free_feasible_box_m3=fb_m3,
            feasible=feasible,
        )
    return out


def add_interference(robot, df, L0=None, engine=None):
    """The interference columns (``models.interference.columns``: interference_free, n_cc, n_cp,
    dmin_m, cc_pairs, cp_cables) of a rigid platform's point table at each row's solved pose
    (x_s, y_s, z_s, rx_s, ry_s, rz_s: where the platform settles), appended in place; a study's
    tables, and ``cdpr point`` and ``cdpr compensate``'s, flag their interfering points with them
    (docs/interference.md).

    Heavy cables (``Robot.heavy``) are tested as their catenaries' polylines under the rest lengths
    the row was solved with: ``L0`` when given, else ``L_TS`` at the row's desired pose (x, y, z,
    rx, ry, rz), the rest lengths ``solve`` commands when it is given none (a study's tables).

    A point mass's table is returned unchanged: it never has cable-cable interference and has no
    platform body, so the columns would say nothing (and its tables keep their bytes). A row whose
    solved pose (or, with heavy cables, a rest length) is not finite (an unsolved point) gets
    interference_free and n_cc, n_cp missing (pandas NA), dmin_m NaN and empty strings: there is no
    pose to test.

    Parameters
    ----------
    robot : Robot
    df : DataFrame
        A rigid platform's point table (``to_frame``: columns x_s, y_s, z_s, rx_s, ry_s, rz_s [m, rad]).
    L0 : array_like (N, m) [m], optional
        The rest lengths of the rows' cables (heavy cables only; ignored for massless ones).
    engine : {"compiled", "numpy"}, optional
        The engine of the heavy cables' catenaries (``cable_interference``).

    Returns
    -------
    DataFrame
        ``df`` (the same object), with the six columns for a rigid platform.
    """
    if robot.point_mass:
        return df
    pose = df[["x_s", "y_s", "z_s", "rx_s", "ry_s", "rz_s"]].to_numpy(dtype=float)
    fin = np.isfinite(pose).all(axis=1)
    if robot.heavy:
        if L0 is None:
            L0 = L_TS(robot, df[["x", "y", "z", "rx", "ry", "rz"]].to_numpy(dtype=float))
        L0 = np.broadcast_to(np.asarray(L0, dtype=float), (len(df), robot.m))
        fin &= np.isfinite(L0).all(axis=1)
    n = len(df)
    free = pd.array(np.zeros(n, dtype=bool), dtype="boolean")
    n_cc = pd.array(np.zeros(n, dtype=np.int64), dtype="Int64")
    n_cp = pd.array(np.zeros(n, dtype=np.int64), dtype="Int64")
    dmin = np.full(n, np.nan)
    cc_pairs = np.full(n, "", dtype=object)
    cp_cables = np.full(n, "", dtype=object)
    if fin.any():
        lengths = L0[fin] if robot.heavy else None
        P, R = pose_arrays(pose[fin, :3], pose[fin, 3:])
        c = columns(cable_interference(robot, P, R, lengths, engine))
        free[fin], n_cc[fin], n_cp[fin] = c["interference_free"], c["n_cc"], c["n_cp"]
        dmin[fin], cc_pairs[fin], cp_cables[fin] = c["dmin_m"], c["cc_pairs"], c["cp_cables"]
    free[~fin], n_cc[~fin], n_cp[~fin] = pd.NA, pd.NA, pd.NA
    df["interference_free"], df["n_cc"], df["n_cp"] = free, n_cc, n_cp
    df["dmin_m"], df["cc_pairs"], df["cp_cables"] = dmin, cc_pairs, cp_cables
    return df


def interfering_at(robot, P_s, rotvec_s=None, R_s=None, desired=None, L0=None, engine=None):
    """Mask (N,) of the points whose cables interfere at their solved poses (``models.interference``):
    what a study's global index, budget and dead-length runs leave out, as the volumes and RW_C
    leave out the rows ``add_interference`` flags (docs/interference.md).

    False where the solved pose is not finite (an unsolved point: no pose to test, and never ok)
    and everywhere on a point mass (no cable-cable interference, no body). Heavy cables are tested
    as their catenaries' polylines under ``L0``, else under ``L_TS`` at the desired poses (the rest
    lengths ``solve`` commands when it is given none).

    Parameters
    ----------
    robot : Robot
    P_s : array_like (N, 3) [m]
        Solved reference points.
    rotvec_s : array_like (N, 3) [rad], optional
        Solved orientations (rotation vectors).
    R_s : array_like (N, 3, 3) [-], optional
        Solved orientations as matrices, in place of ``rotvec_s``.
    desired : array_like (N, 6) [m, rad], optional
        The desired poses (x, y, z, rx, ry, rz): heavy cables' default rest lengths.
    L0 : array_like (N, m) [m], optional
        The rest lengths commanded (heavy cables only).
    engine : {"compiled", "numpy"}, optional
        The engine of the heavy cables' catenaries (``cable_interference``).

    Returns
    -------
    ndarray (N,) bool
    """
    P_s = np.atleast_2d(np.asarray(P_s, dtype=float))
    n = len(P_s)
    out = np.zeros(n, dtype=bool)
    if robot.point_mass:
        return out
    if R_s is None:
        rv = (
            np.zeros((n, 3))
            if rotvec_s is None
            else np.broadcast_to(np.asarray(rotvec_s, dtype=float), (n, 3))
        )
        fin = np.isfinite(P_s).all(axis=1) & np.isfinite(rv).all(axis=1)
    else:
        R_s = np.asarray(R_s, dtype=float).reshape(n, 3, 3)
        fin = np.isfinite(P_s).all(axis=1) & np.isfinite(R_s).all(axis=(1, 2))
    lengths = None
    if robot.heavy:
        if L0 is None:
            if desired is None:
                raise CdprError(
                    f"{robot.source}: heavy cables: interference at solved poses needs the rest lengths or the desired poses"
                )
            L0 = L_TS(robot, np.asarray(desired, dtype=float))
        lengths = np.broadcast_to(np.asarray(L0, dtype=float), (n, robot.m))
        fin &= np.isfinite(lengths).all(axis=1)
        lengths = lengths[fin]
    if fin.any():
        R = pose_arrays(P_s[fin], rv[fin])[1] if R_s is None else R_s[fin]
        out[fin] = ~cable_interference(robot, P_s[fin], R, lengths, engine, closest=False).free
    return out


def cable_interference(robot, P, R, L0=None, engine=None, closest=True):
    """``models.interference.interference`` at poses (P, R), heavy cables as the catenaries under
    ``L0`` solved by the chosen engine (``solve.heavy_cables_at``).

    Parameters
    ----------
    robot : Robot
    P : ndarray (N, 3) [m]
        Platform positions (finite).
    R : ndarray (N, 3, 3) [-]
        Orientations (finite).
    L0 : ndarray (N, m) [m], optional
        Rest lengths (heavy cables only).
    engine : {"compiled", "numpy"}, optional
    closest : bool
        As ``models.interference.interference``'s (False: the flags only).

    Returns
    -------
    Interference
    """
    cables = heavy_cables_at(robot, P, R, L0, engine) if robot.heavy and L0 is not None else None
    return interference(robot, P, R=R, L0=L0, cables=cables, closest=closest)


def desired_lengths(robot, P, rotvec=None, t_min=T_MIN_DEFAULT):
    """The rest lengths a heavy robot's interference at its desired poses is tested under: the
    sag-consistent compensated lengths (``compensation.compensate``, min-norm distribution of the
    tensions at the attachments in [t_min, T_a], ``compensation.heavy_distribution``), under which
    the heavy direct model holds the platform at the pose, as ``cdpr compensate`` plans it.

    Parameters
    ----------
    robot : Robot
    P : array_like (N, 3) [m]
        Desired positions.
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Desired orientations (default identity).
    t_min : float [N]
        Least tension of the distribution.

    Returns
    -------
    L0 : ndarray (N, m) [m]
        NaN where no distribution exists (the pose has no rest lengths to test).
    """
    return compensate(robot, np.atleast_2d(np.asarray(P, dtype=float)), t_min=t_min, rotvec=rotvec)["L0"]


def desired_columns(robot, P, rotvec=None, t_min=T_MIN_DEFAULT):
    """The interference columns (``models.interference.columns``: interference_free, n_cc, n_cp,
    dmin_m, cc_pairs, cp_cables) at desired poses, as ``cdpr grid --interference`` and
    ``cdpr interference --points`` write them. A rigid platform with heavy cables is tested under
    its sag-consistent compensated lengths (``desired_lengths``: the planned catenaries at the
    pose, as ``cdpr compensate`` tests them); where none exist the row has no answer
    (``add_interference``'s missing values). Massless cables, and a point mass, as
    ``models.interference.interference`` gives them (the straight spans).

    Parameters
    ----------
    robot : Robot
    P : array_like (N, 3) [m]
        Desired positions.
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Desired orientations (default identity).
    t_min : float [N]
        Least tension of the heavy cables' distribution.

    Returns
    -------
    dict
        Column name -> array (N,).
    """
    P = np.atleast_2d(np.asarray(P, dtype=float))
    if not robot.heavy or robot.point_mass:
        return columns(interference(robot, P, rotvec))
    rv = (
        np.zeros((len(P), 3)) if rotvec is None else np.broadcast_to(np.asarray(rotvec, dtype=float), P.shape)
    )
    pose = pd.DataFrame(np.column_stack([P, rv]), columns=["x_s", "y_s", "z_s", "rx_s", "ry_s", "rz_s"])
    df = add_interference(robot, pose, L0=desired_lengths(robot, P, rv, t_min))
    return {c: df[c].array for c in COLUMNS}
