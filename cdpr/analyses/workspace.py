"""Point sets and workspace measures: cell-centred grids, deterministic shards, error-limited
volumes (section 3.3.3) and regular workspaces (section 4.1.1).

Section numbers are those of Paty 2021: the error-limited volume V_L holds the points whose pose
error (eq. 14) stays below a limit, R_V = V_L / V_T; RW_max is the largest axis-aligned box inside a
design's workspace and RW_C the intersection of the RW_max of the designs compared. The paper uses
evaluation points "distributed homogeneously" (eq. 15); the grids here are cell-centred. Boxes are
(xmin, xmax, ymin, ymax, zmin, zmax) [m].

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from cdpr.errors import CdprError, ConfigError

#: Bytes of memory per grid point while solving and writing (measured peak RSS / points, rounded up):
#: the bound ``cdpr grid --n`` and the study's size check (``pipeline.study``) apply.
BYTES_PER_POINT = 600


def check_box(box):
    """Validate a box (xmin, xmax, ymin, ymax, zmin, zmax) [m]; returns it as a float array.

    Parameters
    ----------
    box : sequence of 6 float [m]
        xmin, xmax, ymin, ymax, zmin, zmax; finite, each minimum below its maximum.

    Returns
    -------
    box : ndarray (6,) [m]
        The same box as floats. Raises CdprError for a malformed box.
    """
    b = np.asarray(box, dtype=float)
    if b.shape != (6,) or not np.isfinite(b).all():
        raise CdprError(f"a box needs six finite numbers XMIN XMAX YMIN YMAX ZMIN ZMAX, got {list(box)}")
    if not (b[0] < b[1] and b[2] < b[3] and b[4] < b[5]):
        raise CdprError(f"a box needs XMIN < XMAX, YMIN < YMAX and ZMIN < ZMAX, got {b.tolist()}")
    return b


def read_box(path):
    """The ``box`` of a JSON file written by the regular-workspace job (six numbers [m]).

    Parameters
    ----------
    path : str or Path
        A JSON object whose key ``box`` holds XMIN XMAX YMIN YMAX ZMIN ZMAX [m].

    Returns
    -------
    box : list of 6 float [m]
        Checked by ``check_box``; a missing file or a malformed box is one ConfigError naming the file.
    """
    p = Path(path)
    try:
        box = json.loads(p.read_text(encoding="utf-8"))["box"]
    except FileNotFoundError:
        raise ConfigError(p, None, "the box file does not exist") from None
    except (ValueError, KeyError, TypeError) as exc:
        raise ConfigError(
            p,
            "box",
            f"expected a JSON object whose key 'box' holds six numbers XMIN XMAX YMIN YMAX ZMIN ZMAX ({exc})",
        ) from None
    try:
        return check_box(box).tolist()
    except (CdprError, ValueError, TypeError) as exc:
        raise ConfigError(p, "box", str(exc)) from None


def envelope_volume(robot):
    """Volume V_T of the outer envelope [m^3] (Paty 2021 section 3.3.3): the anchors' horizontal
    convex hull from the floor (``Robot.floor_z``, z = 0 by default) to the lowest anchor height (a
    5 m cube for CDPR4, a 54.13 m^3 prism for CDPR3); for a robot that is not a suspended point
    mass, from min(floor, lowest anchor) to the highest anchor (issue 17).

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    float [m^3]
    """
    from scipy.spatial import ConvexHull  # lazy: scipy.spatial is 0.2 s of every grid job's start-up

    A = robot.A
    area = ConvexHull(A[:, :2]).volume  # the area of a 2-D hull
    if not robot.suspended_point_mass:
        return float(area * (A[:, 2].max() - min(robot.floor_z, A[:, 2].min())))
    return float(area * (A[:, 2].min() - robot.floor_z))


def frame_box(robot):
    """Bounding box of the frame [m]: the anchors' horizontal extent, z from the floor
    (``Robot.floor_z``, 0 by default) to the lowest anchor (suspended point-mass robots); for every
    other robot z from min(floor, lowest anchor) to the highest anchor (the frame's extent, issue 17).

    Parameters
    ----------
    robot : Robot
        Supplies the joint points A (m, 3) [m].

    Returns
    -------
    box : list of 6 float [m]
        xmin, xmax, ymin, ymax of the joint points, zmin = the floor, zmax = the lowest joint height.
    """
    lo, hi = robot.A[:, :2].min(axis=0), robot.A[:, :2].max(axis=0)
    if not robot.suspended_point_mass:  # the frame's extent: floor (or lowest anchor) to highest anchor
        z = robot.A[:, 2]
        return [
            float(lo[0]),
            float(hi[0]),
            float(lo[1]),
            float(hi[1]),
            float(min(robot.floor_z, z.min())),
            float(z.max()),
        ]
    return [float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1]), robot.floor_z, float(robot.A[:, 2].min())]


def cell_centres(lo, hi, n):
    """n cell centres of [lo, hi]: lo + (i + 1/2)(hi - lo)/n.

    Parameters
    ----------
    lo : float [m]
        Lower bound of the interval.
    hi : float [m]
        Upper bound of the interval.
    n : int
        Number of cells.

    Returns
    -------
    centres : ndarray (n,) [m]
        Centres of the n equal cells, i = 0 .. n-1.
    """
    return lo + (np.arange(n) + 0.5) * (hi - lo) / n


def grid_points(box, n, start=0, stop=None):
    """Points start..stop-1 of the n^3 cell-centred grid of ``box`` in C order (x slowest, z
    fastest), shape (k, 3). Computing a slice never builds the whole grid.

    Parameters
    ----------
    box : sequence of 6 float [m]
        xmin, xmax, ymin, ymax, zmin, zmax.
    n : int
        Cells per axis.
    start : int
        Index of the first point (0-based, C order).
    stop : int, optional
        Index after the last point, default (and at most) n^3.

    Returns
    -------
    points : ndarray (k, 3) [m]
        k = stop - start points (x, y, z).
    """
    b = check_box(box)
    total = n**3
    stop = total if stop is None else min(stop, total)
    idx = np.arange(start, stop)
    i, rem = np.divmod(idx, n * n)
    j, k = np.divmod(rem, n)
    axes = [cell_centres(b[2 * a], b[2 * a + 1], n) for a in range(3)]
    return np.column_stack([axes[0][i], axes[1][j], axes[2][k]])


def shard_range(total, shard, shards):
    """[start, stop) of shard ``shard`` (0-based) out of ``shards`` equal contiguous slices.

    Parameters
    ----------
    total : int
        Number of items (points) to split.
    shard : int
        0-based index of the shard, 0 <= shard < shards.
    shards : int
        Number of shards, >= 1.

    Returns
    -------
    start : int
        First index of the shard.
    stop : int
        Index after its last; the shards' ranges tile [0, total). Raises CdprError for a bad pair.
    """
    if not (shards >= 1 and 0 <= shard < shards):
        raise CdprError(f"shard must satisfy 0 <= shard < shards, got shard={shard}, shards={shards}")
    return total * shard // shards, total * (shard + 1) // shards


def voxel_mask(df, n, value=None):
    """Boolean (n, n, n) array of a grid table in C order (x, y, z); True where status is ok, the
    point is free of interference where the table says (a rigid platform's study tables carry
    ``interference_free``, ``analyses.interference.add_interference``: an interfering point is no
    workspace) and, if given, ``value`` (a boolean Series/array over rows) holds.

    Parameters
    ----------
    df : DataFrame
        Point table of the n^3 grid in C order (``grid_points``), with a ``status`` column.
    n : int
        Cells per axis; the table must have n^3 rows (else CdprError).
    value : array_like (n^3,) bool, optional
        Extra condition per row.

    Returns
    -------
    mask : ndarray (n, n, n) bool
        Indexed [i_x, i_y, i_z].
    """
    if len(df) != n**3:
        raise CdprError(f"a grid table of n = {n} must have {n**3} rows, got {len(df)}")
    ok = (df["status"] == "ok").to_numpy().copy() & interference_free_rows(df)
    if value is not None:
        ok &= np.asarray(value)
    return ok.reshape(n, n, n)


#: The errors an error-limited volume may bound: table column -> what it is.
ERROR_COLUMNS = {"dp": "the position error |dp| [m]", "dphi": "the orientation error δφ [rad]"}


def error_limited_volume(df, n, box, limit, envelope_volume, column="dp"):
    """Error-limited volume V_L (section 3.3.3) by voxel counting on the n^3 cell-centred grid.

    Returns dict V_L [m^3], R_V = V_L / V_T, and ``V_L_err`` [m^3]: half the volume of the counted
    voxels that touch an uncounted one, an estimate of the voxel-counting error.

    A voxel counts when its centre is ``ok`` (and free of interference, ``voxel_mask``) and its
    pose error |dp| (Paty 2021 eq. 14) is at most ``limit`` (the paper's |dp|_lim, Fig. 13-14); with ``column="dphi"`` when its orientation error
    δφ (the rotation angle between the desired and the reached orientation of a rigid platform, not
    in the paper) is at most ``limit`` [rad].

    Parameters
    ----------
    df : DataFrame
        Point table of the n^3 grid of ``box`` in C order, columns ``status`` and ``column``.
    n : int
        Cells per axis.
    box : sequence of 6 float [m]
        The grid's box.
    limit : float [m] or [rad]
        Error limit |dp|_lim [m] (``column="dp"``) or δφ_lim [rad] (``column="dphi"``).
    envelope_volume : float [m^3]
        Volume V_T of the outer envelope (``envelope_volume``).
    column : {"dp", "dphi"}
        The error the limit applies to: the position error |dp| [m] or the orientation error δφ
        [rad] (tables of spatial robots only; a table without the column raises CdprError).

    Returns
    -------
    dict
        V_L [m^3]; R_V [-]; V_L_err [m^3].
    """
    b = check_box(box)
    if column not in ERROR_COLUMNS:
        raise CdprError(
            f"error_limited_volume: column must be one of {', '.join(ERROR_COLUMNS)}, got {column!r}"
        )
    if column not in df:
        raise CdprError(
            f"error_limited_volume: the grid table has no {column!r} column "
            f"({ERROR_COLUMNS[column]}; δφ exists for spatial robots only)"
        )
    voxel = np.prod((b[1::2] - b[0::2]) / n)
    m = voxel_mask(df, n, df[column].to_numpy() <= limit)
    count = int(m.sum())
    pad = np.pad(m, 1, constant_values=False)
    interior = m.copy()
    for ax in range(3):
        for sh in (1, -1):
            interior &= np.roll(pad, sh, axis=ax)[1:-1, 1:-1, 1:-1]
    boundary = count - int(interior.sum())
    V = count * voxel
    return {"V_L": V, "R_V": V / envelope_volume, "V_L_err": 0.5 * boundary * voxel}


def _largest_rectangle(mask2d):
    """Largest all-True axis-aligned rectangle of a 2-D mask by area: (area, i0, i1, j0, j1), inclusive
    indices, or (0, ...) when empty. Histogram-stack method, O(n^2)."""
    nx, ny = mask2d.shape
    heights = np.zeros(ny, dtype=int)
    best = (0, 0, -1, 0, -1)
    for i in range(nx):
        heights = np.where(mask2d[i], heights + 1, 0)
        stack = []
        for j in range(ny + 1):
            hgt = heights[j] if j < ny else 0
            start = j
            while stack and stack[-1][1] >= hgt:
                s, hs = stack.pop()
                area = hs * (j - s)
                if area > best[0]:
                    best = (area, i - hs + 1, i, s, j - 1)
                start = s
            stack.append((start, hgt))
    return best


def largest_box(mask):
    """Largest axis-aligned box of True voxels in a (nx, ny, nz) mask: (count, (i0, i1, j0, j1, k0, k1)).

    For every z-range [k0, k1] the admissible columns are AND-ed and the largest rectangle found;
    the box of largest voxel count wins (ties: the lowest k0, then k1, in scan order). This is the
    maximum regular workspace RW_max of Paty 2021 section 4.1.1 on a voxel grid.

    Parameters
    ----------
    mask : ndarray (nx, ny, nz) bool
        Admissible voxels (``voxel_mask``).

    Returns
    -------
    count : int
        Number of voxels in the box (0 when the mask has no True voxel).
    cells : tuple of 6 int or None
        Inclusive index ranges (i0, i1, j0, j1, k0, k1); None when count is 0.
    """
    nz = mask.shape[2]
    best = (0, None)
    for k0 in range(nz):
        col = np.ones(mask.shape[:2], dtype=bool)
        for k1 in range(k0, nz):
            col &= mask[:, :, k1]
            if not col.any():
                break
            # upper bound: even the full column area can't beat the best
            if col.sum() * (k1 - k0 + 1) <= best[0]:
                continue
            area, i0, i1, j0, j1 = _largest_rectangle(col)
            if area * (k1 - k0 + 1) > best[0]:
                best = (area * (k1 - k0 + 1), (i0, i1, j0, j1, k0, k1))
    return best


def box_from_cells(box, n, cells):
    """Physical box [xmin, xmax, ymin, ymax, zmin, zmax] covered by inclusive cell ranges.

    Parameters
    ----------
    box : sequence of 6 float [m]
        Box of the n^3 grid.
    n : int
        Cells per axis.
    cells : sequence of 6 int
        Inclusive index ranges (i0, i1, j0, j1, k0, k1) (``largest_box``).

    Returns
    -------
    box : list of 6 float [m]
        The outer faces of the covered cells.
    """
    b = check_box(box)
    step = (b[1::2] - b[0::2]) / n
    out = []
    for a in range(3):
        lo, hi = cells[2 * a], cells[2 * a + 1]
        out += [b[2 * a] + lo * step[a], b[2 * a] + (hi + 1) * step[a]]
    return out


def largest_box_in(df, n, box, value=None):
    """The largest axis-aligned box of a grid table's admissible points (``voxel_mask``: status ok
    and, if given, ``value``, e.g. the wrench-feasible column of ``cdpr grid --wrench-feasible``),
    found by ``largest_box`` (RW_max of Paty 2021 section 4.1.1 on that mask) and measured.

    Parameters
    ----------
    df : DataFrame
        Point table of the n^3 grid of ``box`` in C order (``grid_points``), column ``status``.
    n : int
        Cells per axis.
    box : sequence of 6 float [m]
        The grid's box.
    value : array_like (n^3,) bool, optional
        Extra condition per row.

    Returns
    -------
    dict
        count (voxels in the box, 0 when none is admissible), cells (inclusive index ranges or
        None), box (list of 6 float [m], the outer faces of the cells, or None), volume_m3 (0.0 when
        none) and admissible_m3 (the admissible voxels' volume, by voxel counting) [m^3].
    """
    mask = voxel_mask(df, n, value)
    count, cells = largest_box(mask)
    voxel = box_volume(box) / n**3
    bounds = None if cells is None else box_from_cells(box, n, cells)
    return {
        "count": count,
        "cells": cells,
        "box": bounds,
        "volume_m3": 0.0 if bounds is None else box_volume(bounds),
        "admissible_m3": float(mask.sum() * voxel),
    }


def intersect_boxes(boxes):
    """Intersection of boxes [xmin, xmax, ymin, ymax, zmin, zmax] (RW_C from the RW_max).

    Paty 2021 section 4.1.1: the common regular workspace RW_C is the intersection of the RW_max.

    Parameters
    ----------
    boxes : array_like (k, 6) [m]
        One box per row.

    Returns
    -------
    box : list of 6 float [m]
        The intersection; a minimum above its maximum when the boxes do not overlap
        (``box_volume`` gives 0 there).
    """
    b = np.asarray(boxes, dtype=float)
    out = np.empty(6)
    out[0::2] = b[:, 0::2].max(axis=0)
    out[1::2] = b[:, 1::2].min(axis=0)
    return out.tolist()


def box_volume(box):
    """Volume of a box [xmin, xmax, ymin, ymax, zmin, zmax] (e.g. V_RW_C of Paty 2021 section 4.2.1).

    Parameters
    ----------
    box : sequence of 6 float [m]
        An empty box (a minimum above its maximum) has volume 0.

    Returns
    -------
    volume : float [m^3]
    """
    b = np.asarray(box, dtype=float)
    return float(np.prod(np.maximum(b[1::2] - b[0::2], 0.0)))


def interference_free_rows(df):
    """Boolean mask (N,) of the rows free of interference: the ``interference_free`` column (a
    missing value, an unsolved point, counts as not free), or every row of a table without it (a
    point mass's).

    Parameters
    ----------
    df : DataFrame
        A point table.

    Returns
    -------
    ndarray (N,) bool
    """
    if "interference_free" not in df:
        return np.ones(len(df), dtype=bool)
    return df["interference_free"].astype("boolean").fillna(False).to_numpy(dtype=bool)
