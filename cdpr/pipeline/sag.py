"""What the cables' weight adds (issue 38; the large study, config/studies/large.yaml): the study's
``sag`` section names a robot with heavy cables and its massless twin (the same file with
``linear_density_kg_m: 0``). Two jobs (``cdpr job sag-path``, ``cdpr job sag-corner``; rules in
workflow/rules/large.smk):

- ``sag_path``: the section 3.3.1 path solved on both robots (their trajectory tables, commanded
  with the massless theoretical lengths L_TS as every path of the study) side by side, and the pose
  error that sag adds, |p_s(heavy) - p_s(massless)|;
- ``sag_corner``: the cables of the heavy robot at the corner pose ``sag.corner_m`` drawn from the
  elastic catenary (``scans.catenary_geometry``: the sag-consistent tensions that hold the
  platform there), with each cable's polyline written as a table.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from cdpr import table_io
from cdpr.analyses import scans
from cdpr.errors import CdprError
from cdpr.pipeline import study
from cdpr.pipeline.plots import sag as sag_plots


def _sag(st):
    s = st.get("sag")
    if not s:
        raise CdprError(f"{st.path}: key 'sag': missing; the sag jobs need sag.robot and sag.massless")
    return s


def _path_table(st, files, robot_key):
    """The trajectory table of the path whose robot is ``robot_key`` (its pulley: the study's first)."""
    paths = [k for k in st["trajectories"]["paths"] if study.path_robot(st, k) == robot_key]
    names = {Path(f).name: f for f in files}
    for label in paths:
        for pk in st["pulleys"]:
            if f"{label}_{pk}.csv" in names:
                return table_io.read_table(names[f"{label}_{pk}.csv"])
    raise CdprError(
        f"{st.path}: key 'trajectories.paths': no path table of robot {robot_key!r} among the inputs "
        f"({', '.join(sorted(names))}); the sag path needs one path per robot of `sag`"
    )


def sag_path(st, tables, table, figure):
    """The section 3.3.1 path with and without sag: ||dp|| of the heavy robot and of its massless
    twin at every point of the path (their trajectory tables) and the pose error sag adds, the
    distance between the two solved positions. Columns s, x, y, z (desired), dp_massless_m,
    dp_heavy_m, sag_adds_m, sag_max_m (the largest sag of the point's cables), status_massless,
    status_heavy; a point where either solve is not ``ok`` keeps its row with sag_adds_m blank."""
    s = _sag(st)
    heavy = _path_table(st, tables, s["robot"])
    light = _path_table(st, tables, s["massless"])
    if len(heavy) != len(light) or not np.allclose(heavy[["x", "y", "z"]], light[["x", "y", "z"]]):
        raise CdprError(
            f"{st.path}: key 'trajectories.paths': the paths of {s['robot']} and {s['massless']} differ; "
            "the sag path compares the same path on both robots"
        )
    ok = (heavy["status"] == "ok") & (light["status"] == "ok")
    d = np.linalg.norm(
        heavy[["x_s", "y_s", "z_s"]].to_numpy() - light[["x_s", "y_s", "z_s"]].to_numpy(), axis=1
    )
    out = pd.DataFrame(
        {
            "s": heavy["s"],
            "x": heavy["x"],
            "y": heavy["y"],
            "z": heavy["z"],
            "dp_massless_m": light["dp"],
            "dp_heavy_m": heavy["dp"],
            "sag_adds_m": np.where(ok, d, np.nan),
            "sag_max_m": heavy["sag_max_m"] if "sag_max_m" in heavy else np.nan,
            "status_massless": light["status"],
            "status_heavy": heavy["status"],
        }
    )
    table_io.write_table(out, table)
    sag_plots.sag_path(out, st["name"], s, figure, mode=study.redundancy(st))


def sag_corner(st, table, figure):
    """The heavy robot's cables at ``sag.corner_m`` (the study's orientation) drawn from the elastic
    catenary: one row per polyline point (cable, k, x, y, z [m]; ``sag.shape_points`` per cable, B to
    D), with the cable's tension at B [N] and its sag [m] (``scans.catenary_geometry``)."""
    s = _sag(st)
    robot = study.robot_of(st, s["robot"], dead_length=st["dead_length_m"])
    if not robot.heavy:
        raise CdprError(
            f"{st.path}: key 'sag.robot': robot {s['robot']} has massless cables; name the robot with "
            "cable.linear_density_kg_m > 0"
        )
    geom = scans.pose_geometry(robot, s["corner_m"], study.rotvec(st))
    geom.update(scans.catenary_geometry(robot, geom["p"], geom["R"], n=s["shape_points"]))
    if not np.isfinite(geom["catenary_t"]).all():
        raise CdprError(
            f"{st.path}: key 'sag.corner_m': no tension distribution within the robot's bounds holds the "
            f"platform at {s['corner_m']} m; choose a pose inside the wrench-feasible workspace"
        )
    poly = geom["catenary"]
    m, n = poly.shape[:2]
    out = pd.DataFrame(
        {
            "cable": np.repeat(np.arange(1, m + 1), n),
            "k": np.tile(np.arange(n), m),
            "x": poly[..., 0].ravel(),
            "y": poly[..., 1].ravel(),
            "z": poly[..., 2].ravel(),
            "tension_B_N": np.repeat(geom["catenary_t"], n),
            "sag_m": np.repeat(geom["catenary_sag"], n),
        }
    )
    table_io.write_table(out, table)
    sag_plots.sag_corner(geom, figure, mode=study.redundancy(st))
