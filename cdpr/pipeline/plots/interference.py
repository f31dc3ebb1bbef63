"""The interference-free workspace of a robot at fixed orientations, in plan (docs/interference.md):
drawn from ``cdpr.analyses.interference.interference_workspace`` (nothing solved)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from cdpr.pipeline.plots.style import save


def workspace_plan_figure(name, box, shape, panels, out):
    """The interference-free workspace of a grid at several orientations seen from +z: per
    orientation (a column) the number of interference-free voxels of each (x, y) column of the grid
    (top row) and of those also wrench-feasible (bottom row), out of the column's n_z voxels.

    Parameters
    ----------
    name : str
        The robot's name (the title).
    box : sequence of 6 float [m]
        The grid's box (xmin, xmax, ymin, ymax, zmin, zmax).
    shape : tuple of 3 int
        Cells per axis (n_x, n_y, n_z), the grid of ``interference_workspace``.
    panels : list of (str, dict)
        (label of the orientation, ``interference_workspace(..., wrench_feasible=True)``'s result).
    out : str or Path
        The .png written (a .pdf beside it).

    Returns
    -------
    list of Path
        The files written (``style.save``).
    """
    nx, ny, nz = shape
    k = len(panels)
    fig, axes = plt.subplots(2, k, figsize=(3.6 * k, 6.4), layout="constrained", squeeze=False)
    extent = (box[0], box[1], box[2], box[3])
    im = None
    for c, (label, w) in enumerate(panels):
        free = np.asarray(w["free"], dtype=bool).reshape(nx, ny, nz)
        both = free & np.asarray(w["feasible"], dtype=bool).reshape(nx, ny, nz)
        rows = (
            (free, f"{label}: free {100 * w['fraction']:.1f} %, {w['volume_m3']:.0f} m³"),
            (both, f"free and wrench-feasible {w['free_feasible_m3']:.0f} m³"),
        )
        for r, (mask, title) in enumerate(rows):
            ax = axes[r, c]
            im = ax.imshow(
                mask.sum(axis=2).T,
                origin="lower",
                extent=extent,
                vmin=0,
                vmax=nz,
                cmap="viridis",
                interpolation="nearest",
            )
            ax.set(xlabel="x [m]", ylabel="y [m]", aspect="equal")
            ax.set_title(title, fontsize=8)
            ax.tick_params(labelsize=7)
    fig.colorbar(im, ax=axes, shrink=0.8, label=f"voxels of the column (of {nz})")
    fig.suptitle(
        f"{name}: interference-free voxels per (x, y) column, {nx} × {ny} × {nz} grid of the frame box",
        fontsize=9,
    )
    return save(fig, out)
