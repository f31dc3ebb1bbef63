"""The figures of the comparison of the two redundancy modes (paper rule versus physical equilibrium):
the difference maps, Fig. 12 of both modes on one scale, and Fig. 10, 14, 18, 19 overlaid.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from cdpr.pipeline.plots.style import (
    KIND_COLOURS,
    NOT_OK_COLOUR,
    OKABE_ITO,
    draw_anchors,
    plane_grid,
    round_levels,
    save,
)

#: |‖δp‖ physical − ‖δp‖ paper| [mm] below which a 3-cable point counts as the same solution in both modes.
SAME_MM = 1e-3


def comparison_difference_maps(tables, anchors, z, out):
    """Paper rule versus physics: ‖δp‖_physical − ‖δp‖_paper over the plane at height z, one panel
    per design (rows: robots, columns: pulley designs) on one diverging colour scale centred on 0.
    ``tables`` maps (robot, pulley) to a ``comparison.difference_table``; ``anchors`` maps a robot
    to its anchors A (m, 3). Grey: not ok in either mode; each panel's title counts the points ok
    in only one mode (left out of the difference). A robot with as many cables as degrees of
    freedom has no redundancy: both modes solve the same equations, the panel says so, and counts
    the points where they still found different solutions (more than ``SAME_MM`` apart: the same
    equations can have two; CDPR3 DR at (0, 2.87, 2.5) m hangs from cable 3 alone in physical mode,
    while the paper rule's three taut cables put P* 2 cm outside the anchors' footprint)."""
    robots = list(dict.fromkeys(r for r, _ in tables))
    pulleys = list(dict.fromkeys(p for _, p in tables))
    vmax = max(
        (np.nanmax(np.abs(t["diff"])) for t in tables.values() if t["diff"].notna().any()), default=1.0
    )
    vmax = vmax * 1e3 if vmax > 0 else 1.0
    fig, axes = plt.subplots(
        len(robots),
        len(pulleys),
        figsize=(5.2 * len(pulleys) + 1.2, 5.0 * len(robots)),
        squeeze=False,
        layout="constrained",
    )
    im = None
    for i, rk in enumerate(robots):
        for j, pk in enumerate(pulleys):
            ax = axes[i, j]
            t = tables.get((rk, pk))
            if t is None:
                ax.set_axis_off()
                continue
            A = anchors[rk]
            xs, ys, Z = plane_grid(t, t["diff"].to_numpy() * 1e3)
            ax.set_facecolor(NOT_OK_COLOUR)
            im = ax.pcolormesh(xs, ys, Z, cmap="RdBu_r", vmin=-vmax, vmax=vmax, shading="nearest")
            draw_anchors(ax, A)
            d = t["diff"].dropna() * 1e3
            one = _ok_in_one_mode(t)
            if len(A) <= 3:
                span = "3 cables: no redundancy, both modes equal"
                same = np.abs(d) <= SAME_MM
                if len(d) and same.all():
                    span += f" (|diff| ≤ {np.abs(d).max():.1g} mm)"
                elif len(d):  # the same equations can have two solutions: say so, not "equal"
                    span = (
                        f"3 cables: no redundancy, modes equal at {int(same.sum())} points;\n"
                        f"{int((~same).sum())} differ by up to {np.abs(d).max():.2g} mm (different equilibria)"
                    )
            else:
                span = f"{d.min():+.1f} to {d.max():+.1f} mm" if len(d) else "no common ok point"
            ok1 = f"\nok in one mode only (left out): {one}" if one is not None else ""
            ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{rk} {pk}: {span}{ok1}", aspect="equal")
            ax.title.set_fontsize(8)
    if im is not None:
        fig.colorbar(im, ax=axes.ravel().tolist(), label="‖δp‖ physical − ‖δp‖ paper rule [mm]")
    fig.suptitle(
        f"Physical equilibrium minus the paper rule (best 3-cable subset) at z = {z:g} m", fontsize=10
    )
    return save(fig, out)


def comparison_planes(tables, anchors, z, out):
    """Paty 2021 Fig. 12 in both modes on one scale: ‖δp‖ over the plane at height z, one column
    per design (robot and pulley), the paper rule (top) above the physical equilibrium (bottom); the
    two panels of a column share their filled levels (fine enough for the column's structure,
    labelled lines at every other level) and one colour bar, so a colour means the same error in
    both modes. Grey: not ok in that mode. ``tables`` maps (robot, pulley) to a
    ``comparison.difference_table``; ``anchors`` maps a robot to its anchors A (m, 3)."""
    keys = list(tables)
    fig, axes = plt.subplots(
        2, len(keys), figsize=(4.6 * len(keys), 9.8), squeeze=False, layout="constrained"
    )
    modes = (("paper", "paper rule (best 3-cable subset)"), ("physical", "physical equilibrium"))
    for j, (rk, pk) in enumerate(keys):
        t = tables[(rk, pk)]
        Zs = []
        for mode, _ in modes:
            ok = (t[f"status_{mode}"] == "ok").to_numpy()
            xs, ys, Z = plane_grid(t, np.where(ok, t[f"dp_{mode}"] * 1e3, np.nan))
            Zs.append(Z)
        finite = np.concatenate([Z[np.isfinite(Z)] for Z in Zs])
        levels = round_levels(finite.min(), finite.max(), 10) if finite.size else None
        cf = None
        for i, ((mode, name), Z) in enumerate(zip(modes, Zs)):
            ax = axes[i, j]
            ax.set_facecolor(NOT_OK_COLOUR)
            if levels is not None and len(levels) > 1 and np.isfinite(Z).any():
                cf = ax.contourf(xs, ys, Z, levels=levels, cmap="viridis")
                cs = ax.contour(xs, ys, Z, levels=levels, colors="k", linewidths=0.4)
                ax.clabel(cs, levels[1:-1:2], fmt="%g", fontsize=6)
            draw_anchors(ax, anchors[rk])
            ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{rk} {pk}: {name}", aspect="equal")
            ax.title.set_fontsize(8)
        if cf is not None:
            fig.colorbar(cf, ax=axes[:, j].tolist(), location="bottom", label="‖δp‖ [mm]", shrink=0.8)
    fig.suptitle(
        f"‖δp‖ over the plane at z = {z:g} m in both modes, one scale per design (Fig. 12)", fontsize=10
    )
    return save(fig, out)


def _ok_in_one_mode(t):
    """Number of points of a difference table ok in exactly one mode, or None without the columns."""
    cols = [c for c in t.columns if c.startswith("status")]
    if len(cols) >= 2:
        a, b = (t[c] == "ok" for c in cols[:2])
        return int((a ^ b).sum())
    oks = [c for c in t.columns if c.startswith("dp_")]
    if len(oks) >= 2:
        a, b = (t[c].notna() for c in oks[:2])
        return int((a ^ b).sum())
    return None


#: Line styles of the two redundancy modes in the overlays.
MODE_STYLES = {"paper": "-", "physical": "--"}


def comparison_overlays(data, out):
    """Paper rule and physical equilibrium drawn over each other for Fig. 10 (‖δp‖ along the
    CDPR4 path), Fig. 14 (R_V versus the limit), Fig. 18 (index versus E) and Fig. 19 (the section
    5.2 path at E_mean); solid: paper rule (best 3-cable subset), dashed: physical equilibrium.
    ``data`` maps a mode to {"paths": {label: path table}, "volumes": volumes table,
    "index_vs_E": table, "paths_E": [(design, s, dp)]} (any key may be missing)."""
    fig, axes = plt.subplots(2, 2, figsize=(13, 9), layout="constrained")
    (a, b), (c, d) = axes
    for mode, dd in data.items():
        ls = MODE_STYLES.get(mode, "-")
        tag = "paper rule" if mode == "paper" else "physical"
        for label, df in dd.get("paths", {}).items():
            kind = label.split("_", 1)[-1]
            a.plot(
                df.s,
                df.dp.where(df.status == "ok") * 1e3,
                ls,
                color=KIND_COLOURS.get(kind),
                label=f"{label}, {tag}",
            )
        v = dd.get("volumes")
        if v is not None:
            for (rk, pk), g in v.groupby(["robot", "pulley"], sort=False):
                if rk == "CDPR4":
                    b.plot(g.limit_m * 1e3, g.R_V, ls, color=KIND_COLOURS.get(pk), label=f"{rk} {pk}, {tag}")
        e = dd.get("index_vs_E")
        if e is not None:
            for i, (dk, g) in enumerate(e.groupby("design", sort=False)):
                c.plot(
                    g.E_Pa / 1e9,
                    g.index_m * 1e3,
                    ls,
                    marker="o",
                    ms=3,
                    color=OKABE_ITO[i],
                    label=f"{dk}, {tag}",
                )
        for i, (dk, s, dp) in enumerate(dd.get("paths_E", [])):
            d.plot(s, dp * 1e3, ls, color=OKABE_ITO[i % len(OKABE_ITO)], label=f"{dk} at E_mean, {tag}")
    a.set(
        xlabel="position along the path s [m]", ylabel="‖δp‖ [mm]", title="Fig. 10: CDPR4 section 3.3.1 path"
    )
    b.set(
        xlabel="error limit [mm]",
        ylabel="R_V = V_L / V_T [-]",
        title="Fig. 14: CDPR4 error-limited volume ratio",
    )
    c.set(
        xlabel="Young's modulus E [GPa]",
        ylabel="global index mean ‖δp‖ [mm]",
        title="Fig. 18: index versus E",
    )
    d.set(
        xlabel="position along the path s [m]",
        ylabel="‖δp‖ [mm]",
        title="Fig. 19: section 5.2 path at E_mean",
    )
    for ax in axes.ravel():
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)
    fig.suptitle(
        "Paper rule (solid) against physical equilibrium (dashed): Fig. 10, 14, 18, 19 overlaid", fontsize=10
    )
    return save(fig, out)
