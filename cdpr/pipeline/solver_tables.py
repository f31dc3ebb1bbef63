"""The solver jobs of a study (``cdpr job NAME``): one design of one robot solved over a plane, a
path or a grid, written as a point table.

Each job reads the validated study once and takes every value from it as a value: the robot is the
study's Robot with the design set on it (``study.design_robot``: pulley kind, h, r_p, the dead
length, E), the solver options are the study's (``study.solve_kwargs``: method, redundancy, the fixed
orientation ``rotvec_rad``). Nothing travels as command-line text to be parsed back, and the
Snakemake rules name the study keys each job reads (``uses``), so a change of any of them reruns it.
The tables are those of ``cdpr plane``, ``cdpr trajectory`` and ``cdpr grid`` with the same options; a
rigid platform's add the interference columns at the solved poses
(``analyses.interference.add_interference``: a study flags its interfering points; ``cdpr grid
--interference`` has them at the grid's poses).
"""

from __future__ import annotations

from cdpr import table_io
from cdpr.analyses import scans, workspace
from cdpr.analyses.interference import add_interference
from cdpr.errors import CdprError
from cdpr.models.tension_distribution import distribute_pose
from cdpr.pipeline import study
from cdpr.pipeline.results import Layout
from cdpr.tables import solve_table

#: Least cable tension [N] of the wrench-feasible test of the DOE's workspace grids (spatial robots),
#: the default of ``cdpr grid --t-min``.
WRENCH_T_MIN_N = 100.0


def plane_table(st, robot_key, pulley, table, threads=None):
    """‖δp‖ over the study's plane (``plane``: z_m, n) for robot ``robot_key`` with the pulley design
    ``pulley`` (a key of ``pulleys``): ``cdpr plane``'s table (Paty 2021 section 3.3.2, Fig. 9, 12)."""
    robot = study.design_robot(st, robot_key, _pulley(st, pulley))
    p = st["plane"]
    df = scans.plane(robot, p["z_m"], p["n"], **study.solve_kwargs(st, threads))
    table_io.write_table(add_interference(robot, df), table)


def trajectory_table(st, path_label, pulley, table, threads=None):
    """‖δp‖ along the study's path ``path_label`` (``trajectories.paths``; its robot, ``study.path_robot``)
    with the pulley design ``pulley``, ``trajectories.points`` points: ``cdpr trajectory``'s table
    (Paty 2021 section 3.3.1, Fig. 10)."""
    paths = st["trajectories"]["paths"]
    if path_label not in paths:
        raise CdprError(f"{st.path}: no path {path_label!r} in trajectories.paths (has: {', '.join(paths)})")
    path = paths[path_label]
    robot = study.design_robot(st, study.path_robot(st, path_label), _pulley(st, pulley))
    df = scans.trajectory(
        robot, path["start_m"], path["end_m"], st["trajectories"]["points"], **study.solve_kwargs(st, threads)
    )
    table_io.write_table(add_interference(robot, df), table)


def elasticity_path(st, design, modulus, table, threads=None):
    """‖δp‖ along the section 5.2 path (``elasticity.path``) for the optimal design ``design`` at the
    Young's modulus of ``elasticity.E_path_Pa`` whose label is ``modulus`` (the file name's ``.6g`` spelling,
    ``Layout.E_path``): the study's value itself, not the label parsed back (Fig. 19)."""
    labels = dict(zip(Layout(st, st.path).E_path(), st["elasticity"]["E_path_Pa"]))
    if modulus not in labels:
        raise CdprError(
            f"{st.path}: --modulus {modulus} is none of elasticity.E_path_Pa (labels: {', '.join(labels)})"
        )
    robot = study.design_robot(st, st["doe"]["robot"], _optimal(st, design), E=labels[modulus])
    path = st["elasticity"]["path"]
    df = scans.trajectory(
        robot, path["start_m"], path["end_m"], path["points"], **study.solve_kwargs(st, threads)
    )
    table_io.write_table(add_interference(robot, df), table)


def volume_shard(st, robot_key, pulley, shard, table, threads=None):
    """Shard ``shard`` of the ``volumes.n``³ grid over the frame of robot ``robot_key`` (cut into
    ``volumes.shards``) with the pulley design ``pulley``: ``cdpr grid --frame``'s table (Paty 2021
    section 3.3.3, Fig. 13-14)."""
    robot = study.design_robot(st, robot_key, _pulley(st, pulley))
    v = st["volumes"]
    table_io.write_table(_grid(st, robot, v["n"], int(shard), v["shards"], threads)[0], table)


def workspace_grid(st, test, table, threads=None):
    """The ``doe.workspace_n``³ grid over the frame of the DOE robot for DOE test ``test`` (Table 2),
    ``cdpr grid --frame``'s table; a spatial robot's adds ``feasible`` (a tension distribution in
    [``WRENCH_T_MIN_N``, T_a] holds the platform: its workspace is the wrench-feasible one)."""
    tests = study.doe_tests(st).set_index("test")
    if int(test) not in tests.index:
        raise CdprError(f"{st.path}: no DOE test {test} (tests 1 to {len(tests)})")
    spec = tests.loc[int(test)].to_dict()
    robot = study.design_robot(st, st["doe"]["robot"], spec)
    df, P = _grid(st, robot, st["doe"]["workspace_n"], 0, 1, threads)
    if study.spatial_robots(st):
        df["feasible"] = distribute_pose(robot, P, study.rotvec(st), t_min=WRENCH_T_MIN_N)["feasible"]
    table_io.write_table(df, table)


def _grid(st, robot, n, shard, shards, threads):
    """Shard ``shard`` of ``shards`` of the n³ grid over the robot's frame, solved with the study's
    options (``solve_table``): the table and its points P (k, 3) [m]."""
    box = workspace.check_box(workspace.frame_box(robot))
    start, stop = workspace.shard_range(n**3, shard, shards)
    P = workspace.grid_points(box, n, start, stop)
    return add_interference(robot, solve_table(robot, P, **study.solve_kwargs(st, threads))), P


def _pulley(st, key):
    if key not in st["pulleys"]:
        raise CdprError(f"{st.path}: no pulley design {key!r} in pulleys (has: {', '.join(st['pulleys'])})")
    return st["pulleys"][key]


def _optimal(st, key):
    if key not in st["optimal"]:
        raise CdprError(f"{st.path}: no design {key!r} in optimal (has: {', '.join(st['optimal'])})")
    return st["optimal"][key]
