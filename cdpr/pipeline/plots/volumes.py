"""The figures of the error-limited volumes (Paty 2021 section 3.3.3, the study's ``volumes`` part):
the regions ‖δp‖ ≤ limit (and δφ ≤ limit) as voxels in the frame (Fig. 13), and R_V = V_L / V_T
versus the limit (Fig. 14, and on δφ beyond the paper).
"""

from __future__ import annotations

import warnings

import matplotlib
import matplotlib.pyplot as plt
import numpy as np

from cdpr.pipeline.plots.style import DPHI_SCALE, DPHI_UNIT, KIND_COLOURS, footprint, mode_suffix, save

#: Largest number of voxels per axis drawn in Fig. 13 (matplotlib's voxel rendering is slow).
VOXELS_DRAWN = 24


def _coarsen(a, k, how):
    """Block-reduce a (n, n, n) array by k per axis (n padded with NaN to a multiple of k)."""
    n = np.array(a.shape)
    m = -(-n // k)
    pad = np.full(tuple(m * k), np.nan)
    pad[: n[0], : n[1], : n[2]] = a
    blocks = pad.reshape(m[0], k, m[1], k, m[2], k)
    with warnings.catch_warnings():  # a block with no ok cell has no mean: NaN, as wanted
        warnings.simplefilter("ignore", RuntimeWarning)
        return how(blocks, axis=(1, 3, 5))


def _frame(ax, A):
    """The frame of anchors ``A`` (m, 3) in a 3-D axes: the anchors (pulleys, triangles), the
    footprint at the floor and at the anchors' height, and the vertical posts."""
    path = footprint(A).vertices
    top = float(A[:, 2].max())
    for zz in (0.0, top):
        ax.plot(path[:, 0], path[:, 1], zz, color="k", lw=0.7)
    for x, y in path[:-1]:
        ax.plot([x, x], [y, y], [0.0, top], color="k", lw=0.7)
    ax.scatter(A[:, 0], A[:, 1], A[:, 2], marker="^", color="k", s=20, depthshade=False)


def fig13_volume_view(df, limits, R_V, z_top, title, out, A=None, mode=None, dphi_limits=None, dphi_R_V=None):
    """Paty 2021 Fig. 13: the error-limited region ‖δp‖ <= limit, one panel per limit, drawn as
    opaque voxels (cell-centred grid table ``df`` in C order) inside the frame of anchors ``A``
    (drawn, with the pulleys), every panel on the same limits (the frame's box, z from 0 to
    ``z_top``). Grids finer than ``VOXELS_DRAWN`` per axis are drawn on coarser blocks (a block is
    filled when most of its cells are); R_V is computed on the full grid by the caller. With
    ``dphi_limits`` [rad] and their ``dphi_R_V`` (a rigid platform: ``df`` has ``dphi`` [rad]), a
    second row draws the region δφ <= limit the same way (beyond the paper)."""
    xs, ys, zs = (np.sort(df[c].unique()) for c in ("x", "y", "z"))
    n = (len(xs), len(ys), len(zs))
    k = max(1, -(-max(n) // VOXELS_DRAWN))
    ok = (df.status == "ok").to_numpy().reshape(n)
    lo = np.array([xs[0], ys[0], zs[0]]) - np.array([xs[1] - xs[0], ys[1] - ys[0], zs[1] - zs[0]]) / 2
    step = np.array([xs[1] - xs[0], ys[1] - ys[0], zs[1] - zs[0]]) * k
    m = tuple(-(-np.array(n) // k))
    edges = [lo[a] + step[a] * np.arange(m[a] + 1) for a in range(3)]
    if A is not None:
        box = [(float(A[:, a].min()), float(A[:, a].max())) for a in range(2)] + [
            (0.0, max(z_top, float(A[:, 2].max())))
        ]
    else:
        box = [(edges[0][0], edges[0][-1]), (edges[1][0], edges[1][-1]), (0.0, z_top)]
    rows = [("dp", limits, R_V, 1e3, "‖δp‖", "mm")]
    if dphi_limits:
        rows.append(("dphi", dphi_limits, dphi_R_V, DPHI_SCALE, "δφ", DPHI_UNIT))
    ncols = max(len(r[1]) for r in rows)
    fig = plt.figure(figsize=(5.2 * ncols, 5.6 * len(rows)), layout="constrained")
    for r, (column, lims, rvs, scale, name, unit) in enumerate(rows):
        err = np.where(ok, df[column].to_numpy().reshape(n), np.nan)
        axes = _volume_row(fig, (len(rows), ncols, r), err, lims, rvs, (scale, name, unit), k, edges, box, A)
        fig.colorbar(
            matplotlib.cm.ScalarMappable(
                norm=matplotlib.colors.Normalize(0.0, max(lims) * scale), cmap="viridis"
            ),
            ax=axes,
            location="bottom",
            shrink=0.5,
            label=f"{name} [{unit}]",
        )
    drawn = f" (drawn on {m[0]}x{m[1]}x{m[2]} blocks of the {n[0]}^3 grid)" if k > 1 else ""
    fig.suptitle(title + drawn + mode_suffix(mode), fontsize=10)
    return save(fig, out)


def _volume_row(fig, grid, err, limits, R_V, what, k, edges, box, A):
    """One row of Fig. 13: a 3-D panel per limit of the voxels whose error ``err`` (n, n, n; NaN
    where not ok) is at most the limit, coloured by the error. ``grid`` = (rows, columns, row);
    ``what`` = (display scale, name, unit). Returns the row's axes."""
    rows, ncols, r = grid
    scale, name, unit = what
    norm = matplotlib.colors.Normalize(0.0, max(limits) * scale)
    err_c = _coarsen(err, k, np.nanmean) if k > 1 else err
    X, Y, Z = np.meshgrid(*edges, indexing="ij")
    axes = []
    for j, (lim, rv) in enumerate(zip(limits, R_V)):
        ax = fig.add_subplot(rows, ncols, r * ncols + j + 1, projection="3d")
        axes.append(ax)
        inside = np.where(np.isnan(err), 0.0, (err <= lim).astype(float))
        filled = (_coarsen(inside, k, np.nanmean) >= 0.5) if k > 1 else inside > 0
        colour = plt.get_cmap("viridis")(norm(np.nan_to_num(err_c, nan=0.0) * scale))
        # the limits are set below: without autoscaling after each of the voxels (matplotlib adds one
        # collection per voxel and rescales the view each time: half of the drawing time)
        ax.set_autoscale_on(False)
        faces = ax.voxels(X, Y, Z, filled, facecolors=colour, edgecolor=None, linewidth=0)
        # the PDF draws the voxel faces as images (the PNG is the same; axes, ticks and text stay
        # vector): thousands of faces as vector paths took a third of the job's time
        for collection in faces.values():
            collection.set_rasterized(True)
        if A is not None:
            _frame(ax, A)
        ax.set(
            xlim=box[0], ylim=box[1], zlim=box[2], title=f"{name} ≤ {lim * scale:g} {unit}: R_V = {rv:.2f}"
        )
        ax.set_xlabel("x [m]", labelpad=6)
        ax.set_ylabel("y [m]", labelpad=6)
        ax.set_zlabel("z [m]", labelpad=6)
        ax.tick_params(labelsize=6, pad=0)
        ax.set_box_aspect([box[a][1] - box[a][0] for a in range(3)], zoom=0.85)
    return axes


def fig14_rv(tab, paper, out, mode=None):
    """Paty 2021 Fig. 14: R_V = V_L / V_T versus the error limit, per robot and pulley design;
    ``paper`` rows (robot, pulley, limit_m, R_V) are the paper's values, drawn as markers."""
    fig, ax = plt.subplots(figsize=(7.5, 4.6), layout="constrained")
    robots = list(dict.fromkeys(tab.robot))
    for (rk, pk), g in tab.groupby(["robot", "pulley"], sort=False):
        k = robots.index(rk)
        (line,) = ax.plot(
            g.limit_m * 1e3, g.R_V, ["-", "--", ":"][k % 3], color=KIND_COLOURS.get(pk), label=f"{rk} {pk}"
        )
        p = paper[(paper.robot == rk) & (paper.pulley == pk)]
        if len(p):
            ax.plot(
                p.limit_m * 1e3,
                p.R_V,
                "os^"[k % 3],
                mfc="none",
                ms=7,
                color=line.get_color(),
                label=f"{rk} {pk}: paper",
            )
    _finish_rv(
        ax,
        paper.limit_m,
        1e3,
        r"error limit $\|\delta p\|_{lim}$ [mm]",
        f"Error-limited volume ratio (Fig. 14){mode_suffix(mode)}",
    )
    return save(fig, out)


def fig14_rv_dphi(tab, out, mode=None):
    """Fig. 14 on the orientation error (beyond the paper): R_V = V_L / V_T of the region δφ <= limit
    versus the limit [rad, drawn in mrad], per robot and pulley design (``tab``: robot, pulley,
    limit_rad, R_V, study_limit); the study's limits (``volumes.dphi_limits_rad``) are marked."""
    fig, ax = plt.subplots(figsize=(7.5, 4.6), layout="constrained")
    robots = list(dict.fromkeys(tab.robot))
    for (rk, pk), g in tab.groupby(["robot", "pulley"], sort=False):
        k = robots.index(rk)
        ax.plot(
            g.limit_rad * DPHI_SCALE,
            g.R_V,
            ["-", "--", ":"][k % 3],
            marker="o",
            ms=3,
            color=KIND_COLOURS.get(pk),
            label=f"{rk} {pk}",
        )
    _finish_rv(
        ax,
        tab.limit_rad[tab.study_limit.astype(bool)],
        DPHI_SCALE,
        f"orientation error limit δφ_lim [{DPHI_UNIT}]",
        f"Error-limited volume ratio on δφ (Fig. 14 on the orientation){mode_suffix(mode)}",
    )
    return save(fig, out)


def _finish_rv(ax, limits, scale, xlabel, title):
    """The rest of an R_V panel (Fig. 14): the ``limits`` marked by dotted vertical lines (drawn at
    ``limits * scale``), the axes' labels, the title, the grid and the legend right of the axes."""
    for lim in sorted(set(limits)):
        ax.axvline(lim * scale, color="0.6", ls=":", lw=0.8)
    ax.set(xlabel=xlabel, ylabel=r"$R_V = V_L / V_T$ [-]", title=title)
    ax.title.set_fontsize(9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=1, loc="center left", bbox_to_anchor=(1.01, 0.5))
