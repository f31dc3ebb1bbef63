"""The figures of the study: one function per figure of the papers, each drawing from tables.

Every function takes the tables (DataFrames) a pipeline job wrote beside the figure, draws, and
writes a PNG and a PDF (``save``). Nothing here computes physics: the numbers drawn are the numbers
in the tables. Figure numbers are those of Paty et al. 2021 (Fig. 9-19) and Métillon et al. 2022
(Fig. 7).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
from scipy.spatial import ConvexHull  # noqa: E402

from cdpr.io import atomic  # noqa: E402

#: Colours of the pulley kinds and designs, used by every figure that compares them.
KIND_COLOURS = {"SR": "tab:blue", "DR": "tab:orange", "fixed": "tab:gray"}
#: Colour of the cells that are not ``ok`` in the maps.
NOT_OK_COLOUR = "0.85"


def save(fig, out):
    """Write ``out`` (.png) and its .pdf sibling atomically; returns both paths. The PDF carries no
    creation date, so the same table gives the same bytes."""
    out = Path(out)
    paths = [out, out.with_suffix(".pdf")]
    meta = {".png": None, ".pdf": {"CreationDate": None}}
    for p in paths:
        atomic(
            p,
            lambda tmp, p=p: fig.savefig(
                tmp, format=p.suffix[1:], dpi=150, bbox_inches="tight", metadata=meta[p.suffix]
            ),
        )
    plt.close(fig)
    return paths


def _grid(df, value):
    xs, ys = np.sort(df.x.unique()), np.sort(df.y.unique())
    Z = np.full((len(ys), len(xs)), np.nan)
    ix, iy = np.searchsorted(xs, df.x), np.searchsorted(ys, df.y)
    Z[iy, ix] = value
    return xs, ys, Z


def _round_levels(lo, hi, target=8):
    """Contour levels at round values covering [lo, hi]."""
    if not (np.isfinite(lo) and np.isfinite(hi)) or hi <= lo:
        return None
    raw = (hi - lo) / target
    mag = 10 ** np.floor(np.log10(raw))
    step = min((m * mag for m in (1, 2, 2.5, 5, 10) if m * mag >= raw), default=10 * mag)
    return np.arange(np.floor(lo / step) * step, hi + step, step)


def _anchors(ax, A):
    """Draw the anchors' footprint (the frame's outline seen from above) with cable numbers (1-based)."""
    hull = A[ConvexHull(A[:, :2]).vertices, :2]
    ax.plot(*np.vstack([hull, hull[:1]]).T, color="k", lw=0.6, ls="--")
    for i, (x, y) in enumerate(A[:, :2], start=1):
        ax.plot(x, y, "k^", ms=6)
        ax.annotate(str(i), (x, y), textcoords="offset points", xytext=(4, 4), fontsize=8)


def _not_ok_legend(ax, df):
    counts = df.status[df.status != "ok"].value_counts()
    counts = counts[counts > 0]
    if len(counts):
        ax.legend(
            handles=[
                Patch(
                    color=NOT_OK_COLOUR, label="not ok: " + ", ".join(f"{k} {v}" for k, v in counts.items())
                )
            ],
            fontsize=7,
            loc="upper center",
            bbox_to_anchor=(0.5, -0.2),
        )


def fig7_winch(df, l_pm0, q0, out):
    """Métillon 2022 Fig. 7: (a) drum angle versus the length l_pm, with and without the winch model,
    and (b) the length error δl = k_w (q1 - q_nw). ``df`` has columns l_pm, q1, q2, q_nw, dl."""
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4))
    a.plot(df.l_pm, df.q1, label="q1 (winch model, physical root)")
    a.plot(df.l_pm, df.q_nw, "--", label="q_nw (winch neglected)")
    a.plot([l_pm0], [q0], "ko", label=f"initial point (l_pm0 = {l_pm0:.3f} m, q0 = {q0:g} rad)")
    a.set(xlabel="l_pm [m]", ylabel="drum angle q [rad]", title="(a) drum angle (winch seed Fig. 7a)")
    inset = a.inset_axes([0.55, 0.12, 0.4, 0.3])
    inset.plot(df.l_pm, (df.q1 - df.q_nw) * 1e3, "k-", lw=1)
    inset.set_title("q1 - q_nw [mrad]", fontsize=7)
    inset.tick_params(labelsize=6)
    a.legend(fontsize=7, loc="upper left")
    a.grid(alpha=0.3)
    b.plot(df.l_pm, df.dl * 1e3, "k-", label="δl = k_w (q1 - q_nw)")
    b.axvline(l_pm0, color="0.5", ls=":", label=f"l_pm0 = {l_pm0:.3f} m")
    b.axhline(0.0, color="0.7", lw=0.8)
    b.set(xlabel="l_pm [m]", ylabel="δl [mm]", title="(b) length error (winch seed Fig. 7b)")
    b.legend(fontsize=7)
    b.grid(alpha=0.3)
    return save(fig, out)


def fig9_subsets(tables, A, z, robot_name, out):
    """Paty 2021 Fig. 9: the 3-cable subset that minimises ‖δp‖ at each point of the plane, one
    panel per pulley design. ``tables`` maps a design label to its plane table."""
    labels = sorted({s for df in tables.values() for s in df.subset.astype(str).unique() if s})
    cmap = plt.get_cmap("tab10", max(len(labels), 1))
    fig, axes = plt.subplots(1, len(tables), figsize=(5.2 * len(tables), 4.8), squeeze=False)
    for ax, (label, df) in zip(axes[0], tables.items()):
        code = df.subset.astype(str).map({s: i for i, s in enumerate(labels)}).astype(float)
        code[(df.status != "ok").to_numpy()] = np.nan
        xs, ys, Z = _grid(df, code.to_numpy())
        ax.set_facecolor(NOT_OK_COLOUR)
        im = ax.pcolormesh(xs, ys, Z, cmap=cmap, vmin=-0.5, vmax=len(labels) - 0.5, shading="nearest")
        _anchors(ax, A)
        ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{robot_name} {label} at z = {z:g} m", aspect="equal")
        _not_ok_legend(ax, df)
    cb = fig.colorbar(im, ax=axes[0].tolist(), ticks=range(len(labels)))
    cb.ax.set_yticklabels([f"cables {s}" for s in labels])
    fig.suptitle("Subset of 3 cables that minimises ‖δp‖ (Fig. 9); grey: no admissible subset", fontsize=9)
    return save(fig, out)


def fig9_taut(tables, A, z, robot_name, out):
    """Fig. 9 of the physical study: the set of taut cables of the equilibrium at each point of the
    plane (``redundancy: physical``: every cable may go slack; the paper's Fig. 9 shows instead the
    3-cable subset its rule keeps), one panel per pulley design. ``tables`` maps a design label to
    its plane table (column ``taut``, e.g. '1-2-3-4'); points that are not ok are grey."""
    labels = sorted(
        {s for df in tables.values() for s in df.taut.astype(str).unique() if s},
        key=lambda s: (-len(s.split("-")), s),
    )
    cmap = plt.get_cmap("tab20" if len(labels) > 10 else "tab10", max(len(labels), 1))
    fig, axes = plt.subplots(1, len(tables), figsize=(5.2 * len(tables), 4.8), squeeze=False)
    im = None
    for ax, (label, df) in zip(axes[0], tables.items()):
        code = df.taut.astype(str).map({s: i for i, s in enumerate(labels)}).astype(float)
        code[(df.status != "ok").to_numpy()] = np.nan
        xs, ys, Z = _grid(df, code.to_numpy())
        ax.set_facecolor(NOT_OK_COLOUR)
        im = ax.pcolormesh(xs, ys, Z, cmap=cmap, vmin=-0.5, vmax=len(labels) - 0.5, shading="nearest")
        _anchors(ax, A)
        ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{robot_name} {label} at z = {z:g} m", aspect="equal")
        _not_ok_legend(ax, df)
    if im is not None:
        cb = fig.colorbar(im, ax=axes[0].tolist(), ticks=range(len(labels)))
        cb.ax.set_yticklabels([f"taut {s}" for s in labels])
    fig.suptitle("Taut cables of the physical equilibrium (Fig. 9, physical mode); grey: not ok", fontsize=9)
    return save(fig, out)


def fig10_trajectories(tables, minmax, out):
    """Paty 2021 Fig. 10: ‖δp‖ along the section 3.3.1 paths. ``tables`` maps a design label
    (robot_pulley) to its path table (s, dp, status); ``minmax`` has ok_until_s_m and
    path_length_m per design. Colour: pulley kind; line style: robot. Points that are not ok are
    marked on the axis by status; a dotted line marks each design's last ok point."""
    fig, ax = plt.subplots(figsize=(7, 4.2))
    markers = {"slack": "x", "over_tension": "^", "inaccessible": "s", "not_converged": "d"}
    robots = list(dict.fromkeys(lab.split("_", 1)[0] for lab in tables))
    seen = set()
    for (label, df), (_, row) in zip(tables.items(), minmax.iterrows()):
        ok = df.status == "ok"
        rk, kind = label.split("_", 1) if "_" in label else (label, label)
        style = ["-", "--", ":", "-."][robots.index(rk) % 4]
        (line,) = ax.plot(
            df.s.where(ok), df.dp.where(ok) * 1e3, style, color=KIND_COLOURS.get(kind), label=label
        )
        for st, mk in markers.items():
            sel = df.status == st
            if sel.any():
                seen.add(st)
                ax.plot(df.s[sel], np.zeros(int(sel.sum())), mk, color=line.get_color(), ms=4)
        if np.isfinite(row.ok_until_s_m):
            ax.axvline(row.ok_until_s_m, color=line.get_color(), ls=":", lw=0.8)
    lengths = sorted(set(np.round(minmax.path_length_m, 3)))
    ax.set(
        xlabel="position along the path s [m] (path lengths "
        + ", ".join(f"{v:g}" for v in lengths)
        + " m; dotted: last ok point)",
        ylabel="‖δp‖ [mm]",
        title="‖δp‖ along the section 3.3.1 paths (Fig. 10)",
    )
    ax.grid(alpha=0.3)
    lines = ax.legend(fontsize=7, loc="upper left")
    ax.add_artist(lines)
    proxies = [
        Line2D([], [], ls="", marker=markers[st], color="0.3", label=f"not ok: {st}")
        for st in markers
        if st in seen
    ]
    if proxies:
        ax.legend(handles=proxies, fontsize=7, loc="upper center")
    return save(fig, out)


def fig11_minmax(minmax, out):
    """Paty 2021 Fig. 11: min and max ‖δp‖ along each path, per design (table ``minmax``)."""
    fig, ax = plt.subplots(figsize=(6.5, 4))
    x = np.arange(len(minmax))
    ax.bar(x - 0.2, minmax.dp_min_m * 1e3, 0.4, label="min")
    ax.bar(x + 0.2, minmax.dp_max_m * 1e3, 0.4, label="max")
    ax.set_xticks(x, minmax.design, rotation=30, ha="right")
    ax.set(ylabel="‖δp‖ [mm]", title="Min and max of ‖δp‖ along the paths (Fig. 11)")
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=8)
    return save(fig, out)


def fig12_plane(tables, A, z, robot_name, out):
    """Paty 2021 Fig. 12: iso-contours of ‖δp‖ over the horizontal plane at height z, one panel per
    pulley design of the same robot on ONE colour scale (the comparison is the point). Cells that
    are not ok are grey and counted in a legend; the dashed line is the anchors' outline (cells
    are squares, so the edge of a non-rectangular frame is drawn as steps).

    The small closed contour at the centre of CDPR4 with DR pulleys is in the data, not the
    contouring: the paper's rule takes the least ‖δp‖ of the four 3-cable subsets, which are equal
    at the centre by symmetry and each fall away from it, so ‖δp‖ has a cusp maximum there."""
    vals = [df.dp[df.status == "ok"] for df in tables.values()]
    lo = min((float(v.min()) for v in vals if len(v)), default=np.nan) * 1e3
    hi = max((float(v.max()) for v in vals if len(v)), default=np.nan) * 1e3
    levels = _round_levels(lo, hi, 12)
    fig, axes = plt.subplots(1, len(tables), figsize=(5.2 * len(tables), 5.0), squeeze=False)
    cf = None
    for ax, (label, df) in zip(axes[0], tables.items()):
        ok = (df.status == "ok").to_numpy()
        xs, ys, Z = _grid(df, np.where(ok, df.dp * 1e3, np.nan))
        ax.set_facecolor(NOT_OK_COLOUR)
        if levels is not None and np.isfinite(Z).any():
            cf = ax.contourf(xs, ys, Z, levels=levels, cmap="viridis")
            cs = ax.contour(xs, ys, Z, levels=levels[::2], colors="k", linewidths=0.5)
            ax.clabel(cs, fmt="%g", fontsize=7)
        _anchors(ax, A)
        ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{robot_name} {label} at z = {z:g} m", aspect="equal")
        _not_ok_legend(ax, df)
    if cf is not None:
        fig.colorbar(cf, ax=axes[0].tolist(), label="‖δp‖ [mm]")
    return save(fig, out)


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


def fig13_volume_view(df, limits, R_V, z_top, title, out):
    """Paty 2021 Fig. 13: the error-limited region ‖δp‖ <= limit, one panel per limit, drawn as the
    faces of its voxels (cell-centred grid table ``df`` in C order), z from 0 to ``z_top``. Grids
    finer than ``VOXELS_DRAWN`` per axis are drawn on coarser blocks (a block is filled when most
    of its cells are); R_V is computed on the full grid by the caller."""
    xs, ys, zs = (np.sort(df[c].unique()) for c in ("x", "y", "z"))
    n = (len(xs), len(ys), len(zs))
    k = max(1, -(-max(n) // VOXELS_DRAWN))
    ok = (df.status == "ok").to_numpy().reshape(n)
    dp = np.where(ok, df.dp.to_numpy().reshape(n), np.nan)
    lo = np.array([xs[0], ys[0], zs[0]]) - np.array([xs[1] - xs[0], ys[1] - ys[0], zs[1] - zs[0]]) / 2
    step = np.array([xs[1] - xs[0], ys[1] - ys[0], zs[1] - zs[0]]) * k
    dp_c = _coarsen(dp, k, np.nanmean) if k > 1 else dp
    m = dp_c.shape
    edges = [lo[a] + step[a] * np.arange(m[a] + 1) for a in range(3)]
    X, Y, Z = np.meshgrid(*edges, indexing="ij")
    fig = plt.figure(figsize=(5 * len(limits), 4.8))
    norm = matplotlib.colors.Normalize(0.0, max(limits) * 1e3)
    for j, (lim, rv) in enumerate(zip(limits, R_V)):
        ax = fig.add_subplot(1, len(limits), j + 1, projection="3d")
        inside = np.where(np.isnan(dp), 0.0, (dp <= lim).astype(float))
        filled = (_coarsen(inside, k, np.nanmean) >= 0.5) if k > 1 else inside > 0
        colour = plt.get_cmap("viridis")(norm(np.nan_to_num(dp_c, nan=0.0) * 1e3))
        colour[..., 3] = 0.35
        ax.voxels(X, Y, Z, filled, facecolors=colour, edgecolor=None, linewidth=0)
        ax.set(
            xlabel="x [m]",
            ylabel="y [m]",
            zlabel="z [m]",
            zlim=(0.0, z_top),
            title=f"‖δp‖ ≤ {lim * 1e3:g} mm: R_V = {rv:.2f}",
        )
    fig.colorbar(
        matplotlib.cm.ScalarMappable(norm=norm, cmap="viridis"), ax=fig.axes, shrink=0.6, label="‖δp‖ [mm]"
    )
    drawn = f" (drawn on {m[0]}x{m[1]}x{m[2]} blocks of the {n[0]}^3 grid)" if k > 1 else ""
    fig.suptitle(title + drawn, fontsize=10)
    return save(fig, out)


def fig14_rv(tab, paper, out):
    """Paty 2021 Fig. 14: R_V = V_L / V_T versus the error limit, per robot and pulley design;
    ``paper`` rows (robot, pulley, limit_m, R_V) are the paper's values, drawn as markers."""
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
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
    for lim in sorted(set(paper.limit_m)):
        ax.axvline(lim * 1e3, color="0.6", ls=":", lw=0.8)
    ax.set(
        xlabel=r"error limit $\|\delta p\|_{lim}$ [mm]",
        ylabel=r"$R_V = V_L / V_T$",
        title="Error-limited volume ratio (Fig. 14)",
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    return save(fig, out)


def fig15_doe(tests, out):
    """Paty 2021 Fig. 15: the global index of each DOE test (Table 2)."""
    fig, ax = plt.subplots(figsize=(7, 4.2))
    colours = [KIND_COLOURS.get(k) for k in tests.kind]
    ax.bar(np.arange(len(tests)), tests.index_m * 1e3, color=colours)
    ax.set_xticks(
        np.arange(len(tests)),
        [
            f"T{t}: {k}\nh={h * 1e3:g} r_p={r * 1e3:g} mm"
            for t, k, h, r in zip(tests.test, tests.kind, tests.h_m, tests.r_p_m)
        ],
        fontsize=7,
    )
    ax.set(ylabel="global index mean ‖δp‖ [mm]", title="DOE responses (Fig. 15)")
    ax.grid(axis="y", alpha=0.3)
    return save(fig, out)


def fig16_effects(eff, out):
    """Paty 2021 Fig. 16: effects and interactions of the coded factors on the global index."""
    e = eff[eff.term != "mean"]
    fig, ax = plt.subplots(figsize=(6.5, 4))
    ax.bar(np.arange(len(e)), e.effect * 1e3, color=["tab:green" if v < 0 else "tab:red" for v in e.effect])
    ax.set_xticks(np.arange(len(e)), e.term, rotation=30, ha="right")
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set(
        ylabel="effect on mean ‖δp‖ [mm]",
        title="Effects and interactions (Fig. 16); factors coded -1/+1:\njoint SR/DR, h and r_p low/high level of Table 2",
    )
    ax.title.set_fontsize(9)
    ax.grid(axis="y", alpha=0.3)
    return save(fig, out)


def fig17_maps(tab, valleys, lines, tests, levels, out):
    """Paty 2021 Fig. 17: the global index over the (r_p, h) plane for each pulley kind on one
    colour range, the valley r_p*(h), the fitted line h = k r_p, the DOE field and tests T1-T8, and
    the line's crossing I with the field. ``valleys`` maps a kind to its valley table; ``lines``
    has one row per kind."""
    kinds = list(dict.fromkeys(tab.kind))
    lo, hi = float(tab.index_m.min()) * 1e3, float(tab.index_m.max()) * 1e3
    lv = _round_levels(lo, hi, 20)
    fig, axes = plt.subplots(1, len(kinds), figsize=(5.8 * len(kinds), 5), squeeze=False)
    cf = None
    for ax, kind in zip(axes[0], kinds):
        g = tab[tab.kind == kind]
        piv = g.pivot(index="h_m", columns="r_p_m", values="index_m")
        if piv.shape[0] > 1 and piv.shape[1] > 1 and lv is not None:
            cf = ax.contourf(piv.columns * 1e3, piv.index * 1e3, piv.values * 1e3, levels=lv, cmap="viridis")
        v = valleys[kind]
        ax.plot(v.r_p_star * 1e3, v.h * 1e3, "wo", ms=3, mec="k", mew=0.4, label="valley r_p*(h)")
        line = lines[lines.kind == kind].iloc[0]
        if np.isfinite(line.slope_k):
            rr = np.linspace(0, g.r_p_m.max(), 10)
            ax.plot(rr * 1e3, line.slope_k * rr * 1e3, "r-", label=f"h = {line.slope_k:.2f} r_p")
        r0, r1 = levels["r_p_m"]
        h0, h1 = levels["h_m"]
        ax.add_patch(
            plt.Rectangle((r0 * 1e3, h0 * 1e3), (r1 - r0) * 1e3, (h1 - h0) * 1e3, fill=False, ec="w", ls="--")
        )
        for t in tests[tests.kind == kind].itertuples():
            ax.annotate(
                f"T{t.test}",
                (t.r_p_m * 1e3, t.h_m * 1e3),
                color="w",
                fontsize=8,
                ha="center",
                va="center",
                bbox=dict(boxstyle="round,pad=0.15", fc="k", alpha=0.5),
            )
        if line.r_p_opt_m == line.r_p_opt_m and line.r_p_opt_m is not None:
            ax.plot(line.r_p_opt_m * 1e3, line.h_opt_m * 1e3, "r*", ms=12, label=f"I_{kind}")
        ax.set(
            xlabel="sheave radius r_p [mm]",
            ylabel="lever arm h [mm]",
            title=f"{kind} pulleys (Fig. 17)",
            xlim=(0, g.r_p_m.max() * 1e3),
            ylim=(0, g.h_m.max() * 1e3),
        )
        ax.legend(fontsize=7, loc="lower right")
    if cf is not None:
        fig.colorbar(cf, ax=axes[0].tolist(), label="global index mean ‖δp‖ [mm]")
    return save(fig, out)


def fig18_index_vs_E(tab, E_mean, bands, out):
    """Paty 2021 Fig. 18: the global index of each optimal design versus Young's modulus, with the
    nominal modulus E_mean and the band [min, max] over the range marked."""
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    for dk, g in tab.groupby("design", sort=False):
        (line,) = ax.plot(g.E_Pa / 1e9, g.index_m * 1e3, "o-", ms=3, label=dk)
        b = bands[bands.design == dk].iloc[0]
        ax.axhspan(b.index_min_m * 1e3, b.index_max_m * 1e3, color=line.get_color(), alpha=0.12)
    ax.axvline(E_mean / 1e9, color="k", ls=":", label=f"E_mean = {E_mean / 1e9:g} GPa")
    ax.set(
        xlabel="Young's modulus E [GPa]",
        ylabel="global index mean ‖δp‖ [mm]",
        title="Index versus Young's modulus (Fig. 18); shaded: band",
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return save(fig, out)


def fig19_paths(curves, crossings, out):
    """Paty 2021 Fig. 19: ‖δp‖ along the section 5.2 path for each design (colour) at E_min,
    E_mean, E_max (line style), with the crossings of the E_max and E_min curves marked.
    ``curves`` is a list of (design, E [Pa], s [m], dp [m]); ``crossings`` a table design, s_m."""
    fig, ax = plt.subplots(figsize=(7, 4.2))
    designs = list(dict.fromkeys(c[0] for c in curves))
    Es = sorted({c[1] for c in curves})
    styles = dict(zip(Es, [":", "-", "--"] if len(Es) == 3 else ["-"] * len(Es)))
    colours = dict(zip(designs, plt.rcParams["axes.prop_cycle"].by_key()["color"]))
    for dk, E, s, dp in curves:
        ax.plot(s, dp * 1e3, styles[E], color=colours[dk], label=f"{dk} E = {E / 1e9:g} GPa")
    for r in crossings.itertuples():
        ax.axvline(r.s_m, color=colours.get(r.design, "k"), lw=0.8, alpha=0.6)
        ax.annotate(
            f"{r.design} crossing s = {r.s_m:.2f} m",
            (r.s_m, ax.get_ylim()[1]),
            rotation=90,
            fontsize=6,
            va="top",
            ha="right",
        )
    ax.set(
        xlabel="position along the path s [m]",
        ylabel="‖δp‖ [mm]",
        title="‖δp‖ along the section 5.2 path (Fig. 19)",
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    return save(fig, out)


def dead_length_figure(tab, d_default, out):
    """Sensitivity of the paper-comparable numbers to the dead length d (not given by the paper):
    the CDPR4 plane extremes (left) and the optimal designs' index at E_mean (right)."""
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4))
    for c in [c for c in tab.columns if c.startswith("plane_")]:
        _, pk, stat, _ = c.split("_")
        a.plot(
            tab.d_m,
            tab[c] * 1e3,
            "-" if stat == "max" else "--",
            marker="o",
            ms=3,
            color=KIND_COLOURS.get(pk),
            label=f"{pk} plane {stat}",
        )
    for c in [c for c in tab.columns if c.endswith("_index_m") and "_Emean_" in c]:
        b.plot(tab.d_m, tab[c] * 1e3, marker="o", ms=3, label=f"{c.split('_')[0]} index at E_mean")
    for ax, yl in ((a, "‖δp‖ on the plane [mm]"), (b, "global index mean ‖δp‖ [mm]")):
        ax.axvline(d_default, color="k", ls=":", label=f"default d = {d_default:g} m")
        ax.set(xlabel="dead length d [m]", ylabel=yl)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("Sensitivity of paper-comparable numbers to the dead length d", fontsize=10)
    return save(fig, out)


def comparison_difference_maps(tables, anchors, z, out):
    """Paper rule versus physics: ‖δp‖_physical − ‖δp‖_paper over the plane at height z, one panel
    per design (rows: robots, columns: pulley designs) on one diverging colour scale centred on 0.
    ``tables`` maps (robot, pulley) to a ``comparison.difference_table``; ``anchors`` maps a robot
    to its anchors A (m, 3). Grey: not ok in either mode."""
    robots = list(dict.fromkeys(r for r, _ in tables))
    pulleys = list(dict.fromkeys(p for _, p in tables))
    vmax = max(
        (np.nanmax(np.abs(t["diff"])) for t in tables.values() if t["diff"].notna().any()), default=1.0
    )
    vmax = vmax * 1e3 if vmax > 0 else 1.0
    fig, axes = plt.subplots(
        len(robots), len(pulleys), figsize=(5.0 * len(pulleys), 4.6 * len(robots)), squeeze=False
    )
    im = None
    for i, rk in enumerate(robots):
        for j, pk in enumerate(pulleys):
            ax = axes[i, j]
            t = tables.get((rk, pk))
            if t is None:
                ax.set_axis_off()
                continue
            xs, ys, Z = _grid(t, t["diff"].to_numpy() * 1e3)
            ax.set_facecolor(NOT_OK_COLOUR)
            im = ax.pcolormesh(xs, ys, Z, cmap="RdBu_r", vmin=-vmax, vmax=vmax, shading="nearest")
            _anchors(ax, anchors[rk])
            d = t["diff"].dropna() * 1e3
            span = f"{d.min():+.1f} to {d.max():+.1f} mm" if len(d) else "no common ok point"
            ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{rk} {pk}: {span}", aspect="equal")
    if im is not None:
        fig.colorbar(im, ax=axes.ravel().tolist(), label="‖δp‖ physical − ‖δp‖ paper rule [mm]")
    fig.suptitle(f"Physical equilibrium minus the paper's 3-of-4 rule at z = {z:g} m", fontsize=10)
    return save(fig, out)


#: Colours of the error budget's effects.
EFFECT_COLOURS = {
    "pulley": "tab:blue",
    "elasticity": "tab:green",
    "winch": "tab:red",
    "interaction": "tab:gray",
    "all": "k",
}


def budget_bars(tab, out):
    """Error budget per design over RW_C: (a) stacked bars of each effect's share of the mean
    all-effects error (projection on its direction, so the stack sums to the mean ‖δp_all‖, marked
    by a black tick; negative shares go below zero), beside the mean ‖δp‖ of each effect alone;
    (b) the mean error left after compensating each effect, and all of them. ``tab`` is the budget
    table (design, region, entry, mean_m, share_m, ...); rows of region RW_C are drawn."""
    t = tab[tab.region == "RW_C"]
    designs = list(dict.fromkeys(t.design))
    x = np.arange(len(designs))
    get = lambda d, e, c: float(t[(t.design == d) & (t.entry == e)][c].iloc[0]) * 1e3  # noqa: E731
    fig, (a, b) = plt.subplots(1, 2, figsize=(max(10, 2.4 * len(designs)), 4.8), layout="constrained")
    pos, neg = np.zeros(len(designs)), np.zeros(len(designs))
    for e in ("pulley", "elasticity", "winch", "interaction"):
        v = np.array([get(d, e, "share_m") for d in designs])
        base = np.where(v >= 0, pos, neg)
        a.bar(x - 0.2, v, 0.38, bottom=base, color=EFFECT_COLOURS[e], label=f"{e} (share)")
        pos, neg = np.where(v >= 0, pos + v, pos), np.where(v < 0, neg + v, neg)
    tot = np.array([get(d, "all", "mean_m") for d in designs])
    a.scatter(x - 0.2, tot, marker="_", s=400, color="k", zorder=3, label="mean ‖δp_all‖")
    bottom = np.zeros(len(designs))
    for e in ("pulley", "elasticity", "winch"):
        v = np.array([get(d, e, "mean_m") for d in designs])
        a.bar(x + 0.2, v, 0.38, bottom=bottom, color=EFFECT_COLOURS[e], alpha=0.45, hatch="//")
        bottom += v
    a.axhline(0, color="0.5", lw=0.8)
    a.set_xticks(x, designs, rotation=20)
    a.set(ylabel="mean ‖δp‖ [mm]", title="(a) left: shares of ‖δp_all‖; right (hatched): each effect alone")
    a.legend(fontsize=7)
    entries = ["all", "compensated_pulley", "compensated_elasticity", "compensated_winch", "compensated_all"]
    w = 0.8 / len(entries)
    for i, e in enumerate(entries):
        v = np.array([get(d, e, "mean_m") for d in designs])
        b.bar(x - 0.4 + (i + 0.5) * w, v, w, label=e.replace("compensated_", "compensating "))
    b.set_xticks(x, designs, rotation=20)
    b.set_yscale("symlog", linthresh=1e-3)
    b.set(ylabel="mean ‖δp‖ [mm]", title="(b) error left after compensating each effect")
    b.legend(fontsize=7)
    fig.suptitle("Error budget over RW_C: pulley geometry, cable elasticity, winch exit point", fontsize=10)
    return save(fig, out)


def budget_paths(paths, out):
    """Error budget along the section 3.3.1 paths: ‖δp‖ of each effect alone, all together, the
    interaction and the error left after compensating pulley geometry, versus the arc length s; one
    panel per design. ``paths`` maps a design label to its budget path table (s and one column of
    ‖δp‖ [m] per budget entry, NaN where a variant is not ok)."""
    labels = list(paths)
    cols = 2 if len(labels) > 1 else 1
    rows = int(np.ceil(len(labels) / cols))
    fig, axes = plt.subplots(
        rows, cols, figsize=(6.5 * cols, 3.8 * rows), squeeze=False, layout="constrained"
    )
    for ax, label in zip(axes.ravel(), labels):
        df = paths[label]
        for e in ("pulley", "elasticity", "winch", "interaction", "all"):
            ax.plot(df.s, df[e] * 1e3, color=EFFECT_COLOURS[e], lw=1.8 if e == "all" else 1.1, label=e)
        ax.plot(df.s, df["compensated_pulley"] * 1e3, "k:", lw=1, label="after compensating pulleys")
        ax.set_yscale("log")
        ax.set(xlabel="position along the path s [m]", ylabel="‖δp‖ [mm]", title=label)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=6)
    for ax in axes.ravel()[len(labels) :]:
        ax.set_axis_off()
    fig.suptitle("Error budget along the section 3.3.1 paths", fontsize=10)
    return save(fig, out)


# ---- uncertainty and sensitivity (beyond the paper: cdpr.analyses.uncertainty) ---------------------------
UQ_CASES = ("uncompensated", "compensated")


def _uq_designs(tables):
    return list(dict.fromkeys(d for d, _ in tables))


def uq_index_distribution(linear, tolerances, index_vs_E, paper, out):
    """The global index of each optimal design under per-cable moduli (Monte Carlo, one violin per
    design) beside the common-E band of the paper's section 5.1 (our sweep, and the paper's numbers
    when given), and under every declared parameter (Saltelli's independent rows); uncompensated
    (left) and compensated (right).

    ``linear``, ``tolerances``: {(design, case): table} of ``uq.linear_samples`` and of
    ``uq.sobol``'s rows; ``index_vs_E``: the elasticity sweep (design, E_Pa, index_m) or
    None; ``paper``: {design: (index, minus, plus)} [m]."""
    designs = _uq_designs(linear)
    fig, axes = plt.subplots(1, 2, figsize=(15, 5), gridspec_kw={"width_ratios": [2, 1]})
    colours = dict(zip(designs, plt.rcParams["axes.prop_cycle"].by_key()["color"]))
    for ax, case in zip(axes, UQ_CASES):
        ticks, labels, x = [], [], 0.0
        for dk in designs:
            lin = linear.get((dk, case))
            if lin is None:
                continue
            nominal = lin.loc[lin["sample"] == -1, "index_m"].iloc[0] * 1e3
            vals = lin.loc[lin["sample"] >= 0, "index_m"].dropna().to_numpy() * 1e3
            parts = ax.violinplot([vals], positions=[x], widths=0.7, showextrema=True, showmedians=True)
            for b in parts["bodies"]:
                b.set_facecolor(colours[dk])
                b.set_alpha(0.45)
            ax.plot([x - 0.35, x + 0.35], [nominal, nominal], "k:", lw=1)
            ticks.append(x)
            labels.append(f"{dk}\nper-cable E\nn = {len(vals)}")
            x += 1.0
            if case == "uncompensated" and index_vs_E is not None:
                g = index_vs_E[index_vs_E.design == dk]
                if len(g):
                    lo, hi = g.index_m.min() * 1e3, g.index_m.max() * 1e3
                    ax.vlines(x, lo, hi, color=colours[dk], lw=6, alpha=0.7)
                    ax.plot(x, nominal, "k_", ms=14)
                    ticks.append(x)
                    labels.append(f"{dk}\ncommon E\nours")
                    x += 1.0
                if dk in paper:
                    mid, minus, plus = (v * 1e3 for v in paper[dk])
                    ax.vlines(x, mid - minus, mid + plus, color="0.3", lw=6, alpha=0.7)
                    ax.plot(x, mid, "k_", ms=14)
                    ticks.append(x)
                    labels.append(f"{dk}\ncommon E\npaper")
                    x += 1.0
            tol = tolerances.get((dk, case))
            if tol is not None and len(tol):
                parts = ax.violinplot(
                    [tol.index_m.to_numpy() * 1e3], positions=[x], widths=0.7, showextrema=True
                )
                for b in parts["bodies"]:
                    b.set_facecolor(colours[dk])
                    b.set_alpha(0.2)
                ticks.append(x)
                labels.append(f"{dk}\nall param.\nn = {len(tol)}")
                x += 1.5
        ax.set_xticks(ticks, labels, fontsize=7)
        ax.set(ylabel="global index mean ‖δp‖ over RW_C [mm]", title=f"{case}: dotted = nominal robot")
        ax.grid(alpha=0.3, axis="y")
    fig.suptitle(
        "Global index under per-cable moduli beside the common-E band (Paty 2021 section 5.1)", fontsize=10
    )
    return save(fig, out)


def uq_path_bands(bands, common, out):
    """‖δp‖ along the section 5.2 path: 5-50-95 % band under per-cable moduli for each design
    (columns), uncompensated beside the paper's three common-E curves (top) and compensated
    (bottom). ``bands``: {(design, case): ``uq.path_bands`` table}; ``common``: list of
    (design, E [Pa], s [m], dp [m]) of the common-E paths (Fig. 19)."""
    designs = _uq_designs(bands)
    fig, axes = plt.subplots(2, len(designs), figsize=(5.5 * len(designs), 7), squeeze=False)
    Es = sorted({c[1] for c in common})
    styles = dict(zip(Es, [":", "-", "--"] if len(Es) == 3 else ["-"] * len(Es)))
    for j, dk in enumerate(designs):
        for i, case in enumerate(UQ_CASES):
            ax = axes[i, j]
            b = bands.get((dk, case))
            if b is None:
                ax.set_visible(False)
                continue
            ax.fill_between(
                b.s, b.q05_m * 1e3, b.q95_m * 1e3, color="tab:blue", alpha=0.3, label="5-95 % per-cable E"
            )
            ax.plot(b.s, b.q50_m * 1e3, color="tab:blue", label="median per-cable E")
            ax.plot(b.s, b.dp_nominal_m * 1e3, "k", lw=0.8, alpha=0.6, label="nominal")
            if case == "uncompensated":
                for d, E, s, dp in common:
                    if d == dk:
                        ax.plot(
                            s, dp * 1e3, styles[E], color="tab:red", lw=1, label=f"common E = {E / 1e9:g} GPa"
                        )
            ax.set(xlabel="position along the path s [m]", ylabel="‖δp‖ [mm]", title=f"{dk} {case}")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=6)
    fig.suptitle("‖δp‖ along the section 5.2 path under per-cable moduli (Fig. 19 extended)", fontsize=10)
    fig.tight_layout()
    return save(fig, out)


def uq_sobol(tab, out):
    """Sobol total (bars, 95 % confidence) and first-order (dots) indices of the global index per
    parameter group, for each design (columns) before and after compensation (rows)."""
    g = tab[(tab.level == "group") & (tab.output == "index")]
    designs = list(dict.fromkeys(g.design))
    fig, axes = plt.subplots(2, len(designs), figsize=(5 * len(designs), 6.5), squeeze=False)
    for j, dk in enumerate(designs):
        for i, case in enumerate(UQ_CASES):
            ax = axes[i, j]
            d = g[(g.design == dk) & (g.case == case)]
            x = np.arange(len(d))
            ax.bar(x, d.ST, yerr=d.ST_conf, color="tab:blue", alpha=0.7, capsize=3, label="total ST")
            ax.plot(x, d.S1, "ko", ms=4, label="first order S1")
            ax.set_xticks(x, d.name)
            ax.set(
                ylabel="Sobol index of the global index",
                title=f"{dk} {case}",
                ylim=(min(0, d.S1.min() - 0.05), 1.05),
            )
            ax.grid(alpha=0.3, axis="y")
            ax.legend(fontsize=7)
    fig.suptitle("Which uncertainty drives the global index (SALib, Saltelli sampling)", fontsize=10)
    fig.tight_layout()
    return save(fig, out)


def uq_dominant_map(maps, A, z, out):
    """The parameter whose first-order contribution to the spread of ‖δp‖ is the largest, on the
    plane z (columns: designs; rows: before and after compensation); hatched where it explains less
    than half of the spread. ``maps``: {(design, case): ``uq.dominant_map`` table}."""
    designs = _uq_designs(maps)
    names = sorted({n for df in maps.values() for n in df.dominant.dropna().unique() if n})
    cmap = plt.get_cmap("tab20", max(len(names), 1))
    code = {n: k for k, n in enumerate(names)}
    fig, axes = plt.subplots(2, len(designs), figsize=(5 * len(designs) + 2, 9), squeeze=False)
    for j, dk in enumerate(designs):
        for i, case in enumerate(UQ_CASES):
            ax = axes[i, j]
            df = maps.get((dk, case))
            if df is None:
                ax.set_visible(False)
                continue
            val = df.dominant.map(lambda n: code.get(n, np.nan)).astype(float)
            xs, ys, Z = _grid(df, val.to_numpy())
            _, _, share = _grid(df, df.share.to_numpy())
            ax.pcolormesh(xs, ys, Z, cmap=cmap, vmin=-0.5, vmax=len(names) - 0.5, shading="nearest")
            ax.contourf(
                xs, ys, np.where(share < 0.5, 1.0, np.nan), levels=[0.5, 1.5], colors="none", hatches=["///"]
            )
            _anchors(ax, A)
            ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{dk} {case}", aspect="equal")
    handles = [Patch(color=cmap(code[n]), label=n) for n in names]
    fig.legend(handles=handles, loc="center right", fontsize=7, title="dominant")
    fig.suptitle(f"Dominant uncertain parameter at z = {z:g} m (hatched: it explains < 50 %)", fontsize=10)
    fig.subplots_adjust(right=0.85)
    return save(fig, out)


def uq_agreement(mc, out):
    """The global index of each full-solve Monte Carlo sample against its linearised value, one
    panel per design and case, with the line of equality."""
    keys = sorted(mc)
    fig, axes = plt.subplots(1, len(keys), figsize=(3.6 * len(keys), 3.6), squeeze=False)
    for ax, key in zip(axes[0], keys):
        df = mc[key]
        ax.plot(df.index_full_m * 1e3, df.index_lin_m * 1e3, "o", ms=3)
        lo = np.nanmin([df.index_full_m.min(), df.index_lin_m.min()]) * 1e3
        hi = np.nanmax([df.index_full_m.max(), df.index_lin_m.max()]) * 1e3
        ax.plot([lo, hi], [lo, hi], "k:", lw=1)
        ax.set(xlabel="full solves [mm]", ylabel="linearised [mm]", title=f"{key[0]} {key[1]}")
        ax.grid(alpha=0.3)
    fig.suptitle("Global index per sample: linearised propagation against full solves", fontsize=10)
    return save(fig, out)
