"""MkDocs hook: the figure of "The pulley axis" (spatial.md) drawn from the model at build time.

The picture is ``cdpr.pipeline.plots.robot.pulley_axis_figure`` of ``cdpr.analyses.scans.pulley_plane_geometry``:
a lower wall pulley of config/robots/wall_pulleys.yaml (cable 5, horizontal swivel axis k = +y, the
file's SR pulley h = r_p = 50 mm) and the same pulley as a DR pulley (h = 80 mm, r_p = 50 mm), with
an attachment point B near the pulley and the dead length shortened to 0.25 m (the file's 1.5 m
would put C far off the picture). It is added to the site as ``figures/pulley_axis.png``; nothing is
written under docs/ and nothing generated is committed."""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

from mkdocs.structure.files import File

ROOT = Path(__file__).resolve().parents[2]
#: The site path of the figure (spatial.md links it).
URI = "figures/pulley_axis.png"
#: The robot file, the cable (1-based) whose pulley is drawn and B - A of that cable [m].
ROBOT = ROOT / "config" / "robots" / "wall_pulleys.yaml"
CABLE = 5
B_MINUS_A = (0.30, -0.12, -0.18)
#: The drawn designs: (kind, h [m], r_p [m]); and the dead length of the picture [m].
DESIGNS = (("SR", 0.05, 0.05), ("DR", 0.08, 0.05))
DEAD_LENGTH = 0.25


def draw(out):
    """Draw the pulley-axis figure into ``out`` (.png; a .pdf beside it); returns the paths."""
    if str(ROOT) not in sys.path[:1]:
        sys.path.insert(0, str(ROOT))  # this checkout's cdpr, not another installed one
    import numpy as np

    from cdpr.analyses import scans
    from cdpr.pipeline.plots import robot as robot_plots
    from cdpr.robot import load_robot, with_pulleys

    robot = load_robot(ROBOT)
    i = CABLE - 1
    B = robot.A[i] + np.asarray(B_MINUS_A)
    geoms = [
        scans.pulley_plane_geometry(with_pulleys(robot, kind=k, h=h, r_p=r, dead_length=DEAD_LENGTH), i, B)
        for k, h, r in DESIGNS
    ]
    return robot_plots.pulley_axis_figure(geoms, out)


def on_files(files, config):
    with tempfile.TemporaryDirectory() as tmp:
        png = Path(tmp) / "pulley_axis.png"
        draw(png)
        files.append(File.generated(config, URI, content=png.read_bytes()))
    return files
