"""What a solved point is, in both redundancy modes: the statuses and the per-point columns.

Paper mode (``subsets``) and physical mode (``equilibrium``), numpy or compiled, return dicts of
arrays with the same core keys; the tables built from them (``cdpr.tables.to_frame``) start with the
same columns (``pose_columns``) and label the cables that hold the platform the same way
(``subset_codes`` in paper mode, ``taut_labels`` in physical mode). No pandas here: labels are
integer codes into a list of categories, which ``to_frame`` turns into categoricals.

Status of a point (``STATUSES``):
  ok             an admissible subset exists (paper) / the forces balance with 0 <= t <= T_a (physical);
  over_tension   a cable would need more than its admissible tension T_a;
  slack          the cables would need a negative (pushing) tension;
  not_converged  the solver hit its iteration cap;
  inaccessible   no geometric solution (spheres do not meet, point above the pulleys or outside the
                 anchors, point inside a sheave, coplanar cables).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (eq. 14, section 3.2).
"""

from __future__ import annotations

import numpy as np

STATUSES = ("ok", "slack", "over_tension", "inaccessible", "not_converged")

#: The default floor of a suspended robot [m] (``Robot.floor_z``: the robot file's
#: ``frame.floor_z_m``, 0 by default when every anchor lies above it); the platform hangs between it
#: and the pulleys.
FLOOR_Z = 0.0


def mark_below_floor(res, p, floor_z=FLOOR_Z):
    """Mark the desired points below the floor (z < ``floor_z``) of a suspended point-mass robot
    ``inaccessible`` in a solver's per-point result, whatever the solver found there: one rule for every command and engine (a
    point under the floor cannot be reached, even where the cable model has an equilibrium).

    Parameters
    ----------
    res : dict
        Per-point arrays of a solver (``status`` and, if present, ``status_code``), changed in place.
    p : array_like, shape (N, 3) [m]
        The desired points.
    floor_z : float [m]
        Height of the robot's floor (``Robot.floor_z``).

    Returns
    -------
    dict
        ``res``.
    """
    below = np.asarray(p, dtype=float).reshape(-1, 3)[:, 2] < floor_z
    if below.any():
        if "status_code" in res:
            res["status_code"] = np.where(below, STATUSES.index("inaccessible"), res["status_code"]).astype(
                np.asarray(res["status_code"]).dtype
            )
        res["status"] = np.where(below, "inaccessible", np.asarray(res["status"]).astype(str))
    return res


def subset_label(subset_row):
    """1-based cable numbers joined by '-', e.g. '1-2-3'; '' when no subset.

    Parameters
    ----------
    subset_row : sequence of 3 int
        0-based cable indices of a subset (a row of ``solve_points``' ``subset``); a negative first
        entry means no subset.

    Returns
    -------
    label : str
        The label, e.g. '1-2-3', or '' when there is no subset.
    """
    if subset_row[0] < 0:
        return ""
    return "-".join(str(int(i) + 1) for i in subset_row)


def subset_codes(robot, subset):
    """Codes and categories of the subset labels ('1-2-3', ..., '' when none) of an (N, 3) array of
    0-based subsets (no Python loop per point).

    Parameters
    ----------
    robot : Robot
        Supplies m and ``subsets`` (n_subsets, 3), in lexicographic order.
    subset : array_like (N, 3) int
        0-based cables of each point's subset, -1 when none.

    Returns
    -------
    codes : ndarray (N,) int
        Index into ``labels``.
    labels : list of str, length n_subsets + 1
        ``subset_label`` of every subset, then ''.
    """
    subs = robot.subsets
    labels = [subset_label(s) for s in subs] + [""]
    weights = np.array([robot.m * robot.m, robot.m, 1])
    skey = subs @ weights  # lexicographic order -> sorted keys
    rows = np.asarray(subset).reshape(-1, 3)
    key = rows @ weights
    pos = np.minimum(np.searchsorted(skey, key), len(subs) - 1)
    code = np.where((rows[:, 0] >= 0) & (skey[pos] == key), pos, len(subs))
    return code, labels


def taut_labels(taut):
    """Codes and categories of the taut cables' labels, 1-based numbers joined by '-' ('1-2-4'; ''
    none), from a (N, m) bool array (codes from the bit pattern; no Python loop per point).

    Parameters
    ----------
    taut : array_like (N, m) bool
        Taut cables per point.

    Returns
    -------
    codes : ndarray (N,) int64
        Index into ``labels``: the bit pattern of the taut cables.
    labels : list of str, length 2^m
        All cable sets.
    """
    taut = np.asarray(taut, dtype=bool)
    m = taut.shape[1]
    code = taut.astype(np.int64) @ (1 << np.arange(m))
    labels = ["-".join(str(i + 1) for i in range(m) if c >> i & 1) for c in range(1 << m)]
    return code, labels


def pose_columns(robot, res):
    """The columns every per-point table starts with, from a solver result ``res`` (paper or
    physical mode): x, y, z (desired P), x_s, y_s, z_s (solved P*) [m], dp = |P* - P| (Paty 2021
    eq. 14) [m], t1..tm [N] (NaN where slack).

    Parameters
    ----------
    robot : Robot
        Supplies the number of cables m.
    res : dict
        Arrays p (N, 3), P_s (N, 3), dp (N,), t (N, m).

    Returns
    -------
    dict
        Column name -> (N,) array, in table order: x, y, z, x_s, y_s, z_s, dp, t1..tm.
    """
    cols = {
        "x": res["p"][:, 0],
        "y": res["p"][:, 1],
        "z": res["p"][:, 2],
        "x_s": res["P_s"][:, 0],
        "y_s": res["P_s"][:, 1],
        "z_s": res["P_s"][:, 2],
        "dp": res["dp"],
    }
    cols.update({f"t{i + 1}": res["t"][:, i] for i in range(robot.m)})
    return cols
