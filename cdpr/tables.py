"""Tables of solved points: one row per point with stable column names (pandas).

``to_frame`` turns the per-point arrays of ``cdpr.solve`` (either redundancy mode, with or without
sensitivities, compensation results) into a DataFrame; ``solve_table`` solves and tabulates in one
call. Kept apart from the engine switch (``cdpr.solve``) so that solving one point does not import
pandas.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from cdpr.models import sensitivity
from cdpr.models.equilibrium import hanging_cables
from cdpr.models.results import STATUSES, TAUT_MIN, pose_columns, subset_codes, taut_labels
from cdpr.solve import check_engine, check_redundancy, reached_answer, solve


def to_frame(robot, res, redundancy="paper", rotvec=None):
    """One row per point of a ``solve.solve`` (or ``sensitivities``, or
    ``compensation.compensated_pose``) result, with stable column names (SI units).

    Parameters
    ----------
    robot : Robot
        Supplies m and the subsets.
    res : dict
        The per-point arrays (``models.results``).
    redundancy : {"paper", "physical"}
        The mode that produced ``res``.
    rotvec : array (3,) or (N, 3) [rad], optional
        The orientation the solve was given (``--rotvec`` or a points table's rx, ry, rz), or None.
        A point-mass robot carries it through: its table then has the orientation columns of a
        rigid platform's too (rx, ry, rz given, rx_s, ry_s, rz_s = the given ones, dphi = 0;
        unique where ``res`` has it). None (default): the table has no orientation columns (a
        rigid platform's has them always).

    Returns
    -------
    DataFrame
        ``results.pose_columns`` (x, y, z, x_s, y_s, z_s, dp [m], t1..tm [N]); paper mode: subset
        (label '1-2-3', '' when none), n_taut (the cables with t > ``results.TAUT_MIN``), iterations, status; physical mode: taut (label of the taut
        cables, '1-2-3-4'), n_taut, iterations, status. The status categories are
        ``res["statuses"]`` when given (``compensation.COMP_STATUSES``), else ``results.STATUSES``.
        When ``res`` holds sensitivities (key ``S``): then dx_d<θ>, dy_d<θ>, dz_d<θ> per parameter
        [m per unit of θ] (``sensitivity.sensitivity_columns``) and smooth; a 6-DoF result's also
        dphix_d<θ>, dphiy_d<θ>, dphiz_d<θ> [rad per unit] (``sensitivity.pose_sensitivity_columns``). A 6-DoF result of a
        rigid platform (``equilibrium.solve``, key ``rotvec_s``, robot not a point mass): the
        physical mode's columns and rx, ry, rz (desired) and rx_s, ry_s, rz_s (reached) rotation
        vectors [rad] after dp, dphi [rad], and unique last; then n_folds, reached_is_global where
        ``res`` has them (``solve.reach_where_multiple``). A result with heavy cables (key
        ``sag_max``) adds sag_max_m [m], the largest sag of the point's cables, after status; a
        rigid platform's also n_holding, the taut cables less those that hang at about their own
        weight (``equilibrium.hanging_cables``: every heavy cable pulls, so n_taut is m).
    """
    df = _frame(robot, res, redundancy)
    if check_redundancy(redundancy) == "physical" and "rotvec_s" in res and not robot.point_mass:
        _orientation_columns(df, res["rotvec"], res["rotvec_s"], res["dphi"], res["unique"])
    elif rotvec is not None:  # a point mass given an orientation: carried through (docs/spatial.md)
        rv = np.broadcast_to(np.asarray(rotvec, dtype=float), (len(df), 3))
        _orientation_columns(
            df,
            res.get("rotvec", rv),
            res.get("rotvec_s", rv),
            res.get("dphi", np.zeros(len(df))),
            res.get("unique"),
        )
    if "n_folds" in res:  # continued where the equilibrium is not unique (solve.reach_where_multiple)
        df["n_folds"] = res["n_folds"]
        df["reached_is_global"] = res["reached_is_global"]
    return df


def _frame(robot, res, redundancy):
    """``to_frame`` of a point-mass result (the columns its docstring lists)."""
    df = pd.DataFrame(pose_columns(robot, res))
    if redundancy == "paper":
        codes, labels = subset_codes(robot, res["subset"])
        df["subset"] = pd.Categorical.from_codes(codes, categories=labels)
        t = np.asarray(res["t"], dtype=float).reshape(len(df), robot.m)
        with np.errstate(invalid="ignore"):
            df["n_taut"] = (t > TAUT_MIN).sum(axis=1).astype(np.int8)  # the cables that hold it (NaN: slack)
    else:
        codes, labels = taut_labels(res["taut"])
        df["taut"] = pd.Categorical.from_codes(codes, categories=labels)
        df["n_taut"] = res["n_taut"]
    df["iterations"] = res["iterations"]
    statuses = list(res.get("statuses", STATUSES))
    codes = (
        res["status_code"]
        if "status_code" in res
        else pd.Categorical(res["status"], categories=statuses).codes
    )
    df["status"] = pd.Categorical.from_codes(codes, categories=statuses)
    if "sag_max" in res:  # heavy cables (issue 38): the largest sag of the point's cables [m]
        df["sag_max_m"] = res["sag_max"]
        if "L0" in res:  # a rigid platform's: the taut cables that hold it, not those hanging at
            # about their own weight (a point mass's result does not carry its L0)
            hanging = hanging_cables(res["t"], robot.arrays.w, robot.arrays.ES, res["L0"])
            df["n_holding"] = (np.asarray(res["taut"], dtype=bool) & ~hanging).sum(axis=1).astype(np.int8)
    if "S" in res:
        S = res["S"]
        flat = np.swapaxes(S, 1, 2).reshape(len(S), -1)
        columns = (
            sensitivity.pose_sensitivity_columns if S.shape[1] == 6 else sensitivity.sensitivity_columns
        )(res["names"])
        sens = pd.DataFrame(flat, columns=columns)
        sens["smooth"] = res["smooth"]
        df = pd.concat([df, sens], axis=1)
    return df


def _orientation_columns(df, rotvec, rotvec_s, dphi, unique=None):
    """Insert rx, ry, rz (given), rx_s, ry_s, rz_s (reached) [rad] and dphi [rad] after dp, and
    append unique when given (in place): the orientation columns of ``to_frame``."""
    at = list(df.columns).index("dp") + 1
    for k, name in enumerate(("rx", "ry", "rz")):
        df.insert(at + k, name, rotvec[:, k])
    for k, name in enumerate(("rx_s", "ry_s", "rz_s")):
        df.insert(at + 3 + k, name, rotvec_s[:, k])
    df.insert(at + 6, "dphi", dphi)
    if unique is not None:
        df["unique"] = unique


#: Points solved per batch by ``solve_table``: bounds memory (about 2 kB per point and subset) and
#: keeps arrays in cache (the compiled kernels' own chunk of points per thread is
#: ``cdpr.compiled._kernels.CHUNK``).
TABLE_BATCH = 20000


def solve_table(
    robot,
    p,
    method="newton",
    chunk=TABLE_BATCH,
    engine=None,
    threads=None,
    redundancy=None,
    L0=None,
    equilibrium=None,
    **options,
):
    """Solve poses of any robot (``solve.solve``) as a DataFrame (``to_frame``).

    Parameters
    ----------
    robot : Robot
    p : array (N, 3) or (N, 6) [m, rad]
        Desired platform positions, or poses.
    method : {"newton", "fixed_point"}
        DEGM_E solver of paper mode (``direct.degm_e``).
    chunk : int
        Points per numpy solve of paper mode (bounds memory).
    engine : {"compiled", "numpy", None}
        None (default): compiled for Newton, numpy for the fixed point. ``"compiled"`` runs the
        numba kernels over all points in parallel (``threads`` caps the threads); Newton only.
        ``"numpy"`` runs the references (paper mode: ``cdpr.models.subsets.solve_points`` in chunks
        of ``chunk`` points, the only one for the fixed point). Both give the same table (tested).
        Another pair raises CdprError.
    threads : int, optional
    redundancy : {"paper", "physical"}, optional
        The paper's 3-cable subset rule (point masses), or the physical equilibrium on all cables;
        default paper for a point mass, physical for a rigid platform (``solve.check_redundancy``).
    L0 : array (N, m) [m], optional
        Commanded rest lengths, physical mode only.
    equilibrium : {"reached", "global"}, optional
        Physical mode's answer where the restarts find more than one equilibrium: the one reached
        by continuation (default, ``solve.reach_where_multiple``; the table then gets the columns
        n_folds and reached_is_global) or the lowest energy (``global``). Where every point's
        equilibrium is unique the two are the same and the table is as before.
    **options
        ``rotvec`` (a fixed orientation [rad], (3,) or (N, 3)) and the solver's options.

    Returns
    -------
    DataFrame, one row per point (``to_frame``; given ``rotvec``, with its orientation columns)."""
    p = np.atleast_2d(np.asarray(p, dtype=float))
    redundancy = check_redundancy(redundancy, robot)
    run = {"method": method, "threads": threads, "redundancy": redundancy}
    if redundancy != "paper" or L0 is not None or not robot.suspended_point_mass or "rotvec" in options:
        res = solve(robot, p, engine=engine, L0=L0, **run, **options)
        if redundancy == "physical":  # issue 39: the reached equilibrium where it is not unique
            res = reached_answer(robot, res, equilibrium, engine, threads)
        return to_frame(robot, res, redundancy, options.get("rotvec"))
    engine = check_engine(engine, method)
    if engine == "compiled":
        return to_frame(robot, solve(robot, p, engine=engine, **run, **options))
    starts = range(0, len(p), chunk) if len(p) else [0]
    frames = [
        to_frame(robot, solve(robot, p[i : i + chunk], engine=engine, **run, **options)) for i in starts
    ]
    return pd.concat(frames, ignore_index=True)
