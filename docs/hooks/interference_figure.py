"""MkDocs hook: the interference-free workspace of CoGiRo (interference.md) computed and drawn from
the model at build time.

``cdpr.analyses.interference.interference_workspace`` of config/robots/cogiro_massless.yaml (CoGiRo
with straight, massless cables: the grid's desired poses are geometry, not solved equilibria) over the
cell-centred 21 x 21 x 11 grid of its frame box at the identity and at 15 degrees about x, y and z,
with its intersection with the wrench-feasible workspace (tensions in [100 N, T_a]), drawn by
``cdpr.pipeline.plots.interference.workspace_plan_figure``. It is added to the site as
``figures/interference_workspace.png``; nothing is written under docs/ and nothing generated is
committed. Run as a script (``.venv/bin/python docs/hooks/interference_figure.py OUT.png``) it
writes the figure to OUT.png and prints the numbers of the page's table."""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

from mkdocs.structure.files import File

ROOT = Path(__file__).resolve().parents[2]
#: The site path of the figure (interference.md links it).
URI = "figures/interference_workspace.png"
ROBOT = ROOT / "config" / "robots" / "cogiro_massless.yaml"
#: The grid (cells per axis) and the orientations drawn: (label, rotation vector [deg]).
SHAPE = (21, 21, 11)
ORIENTATIONS = (
    ("identity", (0.0, 0.0, 0.0)),
    ("15° about x", (15.0, 0.0, 0.0)),
    ("15° about y", (0.0, 15.0, 0.0)),
    ("15° about z", (0.0, 0.0, 15.0)),
)


def draw(out):
    """Compute the four workspaces and draw the figure into ``out`` (.png; a .pdf beside it);
    returns the (label, result) pairs."""
    if str(ROOT) not in sys.path[:1]:
        sys.path.insert(0, str(ROOT))  # this checkout's cdpr, not another installed one
    import numpy as np

    from cdpr.analyses.interference import interference_workspace
    from cdpr.analyses.workspace import frame_box
    from cdpr.pipeline.plots.interference import workspace_plan_figure
    from cdpr.robot import load_robot

    robot = load_robot(ROBOT)
    box = frame_box(robot)
    panels = [
        (label, interference_workspace(robot, box, SHAPE, np.radians(deg), wrench_feasible=True))
        for label, deg in ORIENTATIONS
    ]
    workspace_plan_figure(robot.name, box, SHAPE, panels, out)
    return panels


def on_files(files, config):
    with tempfile.TemporaryDirectory() as tmp:
        png = Path(tmp) / "interference_workspace.png"
        draw(png)
        files.append(File.generated(config, URI, content=png.read_bytes()))
    return files


if __name__ == "__main__":
    for label, w in draw(Path(sys.argv[1])):
        print(
            f"{label}: free {w['free_points']} of {w['points']} ({100 * w['fraction']:.1f} %), "
            f"{w['volume_m3']:.1f} m3, box {w['box_m3']:.1f} m3; cable-platform at {w['cp_points']}, "
            f"cable-cable at {w['cc_points']}; wrench-feasible {w['feasible_points']}, "
            f"free and feasible {w['free_feasible_points']} ({w['free_feasible_m3']:.1f} m3, "
            f"box {w['free_feasible_box_m3']:.1f} m3)"
        )
