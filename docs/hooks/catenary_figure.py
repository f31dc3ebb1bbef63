"""MkDocs hook: the figure of heavy_cables.md, cube50's cables at a corner pose drawn from the elastic
catenary, at build time.

The picture is ``cdpr.pipeline.plots.sag.sag_corner`` of ``cdpr.analyses.scans.pose_geometry`` (with
``scans.catenary_geometry``: the sag-consistent tensions that hold the platform there) for
config/robots/cube50.yaml at the large study's corner pose (config/studies/large.yaml,
``sag.corner_m``; the study's ``sag/corner.png`` is the same figure). It is added to the site as
``figures/catenary_corner.png``; nothing is written under docs/ and nothing generated is committed."""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import yaml
from mkdocs.structure.files import File

ROOT = Path(__file__).resolve().parents[2]
#: The site path of the figure (heavy_cables.md links it).
URI = "figures/catenary_corner.png"
#: The study whose robot, corner pose, mode and polyline points the figure takes.
STUDY = ROOT / "config" / "studies" / "large.yaml"


def draw(out):
    """Draw the corner figure into ``out`` (.png; a .pdf beside it); returns the paths."""
    if str(ROOT) not in sys.path[:1]:
        sys.path.insert(0, str(ROOT))  # this checkout's cdpr, not another installed one
    from cdpr.analyses import scans
    from cdpr.pipeline.plots import sag as sag_plots
    from cdpr.robot import load_robot

    st = yaml.safe_load(STUDY.read_text(encoding="utf-8"))
    sag = st["sag"]
    robot = load_robot(ROOT / st["robots"][sag["robot"]])
    geom = scans.pose_geometry(robot, sag["corner_m"])
    geom.update(scans.catenary_geometry(robot, geom["p"], geom["R"], n=sag["shape_points"]))
    return sag_plots.sag_corner(geom, out, mode=st["redundancy"])


def on_files(files, config):
    with tempfile.TemporaryDirectory() as tmp:
        png = Path(tmp) / "catenary_corner.png"
        draw(png)
        files.append(File.generated(config, URI, content=png.read_bytes()))
    return files
