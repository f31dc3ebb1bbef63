"""The paper's analyses as functions of a robot: trajectories (section 3.3.1), planes (3.3.2),
error-limited volumes (3.3.3), regular workspaces and the global index (4.1), factorial designs
(4.2), optimal lines (4.3). Each returns a DataFrame or a small dict; no files, no Snakemake."""

from __future__ import annotations

import numpy as np

from .solve import solve_table
from .workspace import cell_centres, frame_box


def trajectory_points(start, end, n):
    """n evenly spaced points on the segment start -> end and their arc length s [m]."""
    start, end = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    f = np.linspace(0.0, 1.0, n)
    return start + f[:, None] * (end - start), f * np.linalg.norm(end - start)


def trajectory(robot, start, end, n, method="newton", **solver):
    """|dp| along a straight path (Fig. 10, 19): the point table plus the arc length ``s``."""
    P, s = trajectory_points(start, end, n)
    df = solve_table(robot, P, method=method, **solver)
    df.insert(0, "s", s)
    return df


def plane_points(robot, z, n):
    """n x n cell centres over the anchors' horizontal bounding box at height z (Fig. 9, 12)."""
    x0, x1, y0, y1, _, _ = frame_box(robot)
    X, Y = np.meshgrid(cell_centres(x0, x1, n), cell_centres(y0, y1, n), indexing="ij")
    return np.column_stack([X.ravel(), Y.ravel(), np.full(X.size, float(z))])


def plane(robot, z, n, method="newton", **solver):
    """|dp| over the horizontal plane at height z (Fig. 12) with the chosen subsets (Fig. 9)."""
    return solve_table(robot, plane_points(robot, z, n), method=method, **solver)


def ok_extremes(df):
    """min and max |dp| over the rows with status ok (NaN when there are none)."""
    ok = df.loc[df["status"] == "ok", "dp"]
    return (float(ok.min()), float(ok.max())) if len(ok) else (float("nan"), float("nan"))


def crossings(s, a, b):
    """Arc lengths where curve a - b changes sign (linear interpolation), e.g. E_max vs E_min (Fig. 19)."""
    s, diff = np.asarray(s), np.asarray(a) - np.asarray(b)
    good = np.isfinite(diff)
    s, diff = s[good], diff[good]
    idx = np.flatnonzero(np.sign(diff[:-1]) * np.sign(diff[1:]) < 0)
    return [float(s[i] - diff[i] * (s[i + 1] - s[i]) / (diff[i + 1] - diff[i])) for i in idx]
