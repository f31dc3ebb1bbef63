"""The figures of the uncertainty study (beyond the paper: ``cdpr.analyses.uncertainty``,
``cdpr.pipeline.uq``): the global index under per-cable moduli and every declared parameter, the
bands along the path, the Sobol indices, the dominant parameter and what compensation leaves on
the plane, and the agreement of the linearisation with full solves. Each figure loops over the
``responses`` it is given (``RESPONSES``): ‖δp‖ alone for a suspended point mass, ‖δp‖ and δφ (a panel
for each) for a robot solved as a pose (the ``responses`` of ``cdpr.analyses.uncertainty.PoseErrorModel``).
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from cdpr.analyses.uncertainty import CASES
from cdpr.pipeline.plots.robot import INTERFERING_COLOUR
from cdpr.pipeline.plots.style import (
    MODE_TITLES,
    NOT_OK_COLOUR,
    OKABE_ITO,
    draw_anchors,
    mode_suffix,
    plane_grid,
    round_levels,
    save,
)

# ---- uncertainty and sensitivity (beyond the paper: cdpr.analyses.uncertainty) ---------------------------
UQ_CASES = CASES  # the compensated case only where the study ran it (``study.uq_cases``)


def _interfering_cells(ax, df):
    """Draw the points of a ``uq.dominant_map`` table whose nominal robot interferes at its solved
    pose (column ``interfering``: left out of the map) as ``INTERFERING_COLOUR`` cells crossed by a
    hatch (tab20's own pink stays distinct); returns the panel title's words on them, "" when none."""
    if "interfering" not in df:
        return ""
    bad = df["interfering"].astype("boolean").fillna(False).to_numpy(dtype=bool)
    if not bad.any():
        return ""
    xs, ys, Z = plane_grid(df, np.where(bad, 1.0, np.nan))
    ax.pcolormesh(xs, ys, Z, cmap=ListedColormap([INTERFERING_COLOUR]), shading="nearest")
    ax.contourf(xs, ys, Z, levels=[0.5, 1.5], colors="none", hatches=["xx"])
    return f"\npink crossed: {int(bad.sum())} points with interfering cables, left out"


def _uq_designs(tables):
    return list(dict.fromkeys(d for d, _ in tables))


def _panels(axes, designs, rows, tables):
    """The panels of a designs x rows figure (``uq_path_bands``, ``uq_dominant_map``): column j a
    design, row i a (case, response key); yields (design, case, key, RESPONSES[key], ax, table) for
    each panel with a table in ``tables`` {(design, case): table}, column by column, and hides the
    others."""
    for j, dk in enumerate(designs):
        for i, (case, key) in enumerate(rows):
            ax = axes[i, j]
            table = tables.get((dk, case))
            if table is None:
                ax.set_visible(False)
                continue
            yield dk, case, key, RESPONSES[key], ax, table


def _uq_cases(tables):
    """The cases present among {(design, case): table}, in ``UQ_CASES`` order (a paper-mode study
    has no compensated case: ``study.uq_cases``)."""
    cases = {c for _, c in tables}
    return [c for c in UQ_CASES if c in cases]


#: The responses of the figures: label, unit, scale to it, and the columns of each table: global
#: index, full/linearised index, path quantile suffix, path nominal, Sobol output, map columns.
RESPONSES = {
    "dp": {
        "label": "‖δp‖",
        "unit": "mm",
        "scale": 1e3,
        "index": "index_m",
        "full": "index_full_m",
        "lin": "index_lin_m",
        "q": "_m",
        "nominal": "dp_nominal_m",
        "output": "index",
        "dominant": "dominant",
        "share": "share",
        "rms": "rms_m",
    },
    "dphi": {
        "label": "δφ",
        "unit": "mrad",
        "scale": 1e3,
        "index": "index_phi_rad",
        "full": "index_phi_full_rad",
        "lin": "index_phi_lin_rad",
        "q": "_phi_rad",
        "nominal": "dphi_nominal_rad",
        "output": "index_phi",
        "dominant": "dominant_phi",
        "share": "share_phi",
        "rms": "rms_phi_rad",
    },
}


def _colour_violin(parts, colour, alpha):
    """Bodies, whiskers (extrema bars) and medians of a violin in one colour."""
    for b in parts["bodies"]:
        b.set_facecolor(colour)
        b.set_edgecolor(colour)
        b.set_alpha(alpha)
    for key in ("cbars", "cmins", "cmaxes", "cmedians"):
        if key in parts:
            parts[key].set_color(colour)


def uq_index_distribution(linear, tolerances, index_vs_E, paper, out, mode=None, responses=("dp",)):
    """The global index of each optimal design under per-cable moduli (Monte Carlo, one violin per
    design) beside the common-E band of the paper's section 5.1 (our sweep, and the paper's numbers
    when given), and under every declared parameter (Saltelli's independent rows); one column per
    case the study ran (uncompensated, compensated: ``study.uq_cases``), one row per response
    (‖δp‖, then δφ for a pose). Each design has one colour (violins, whiskers, bars); the key under
    the panels says what each mark is.

    ``linear``, ``tolerances``: {(design, case): table} of ``uq.linear_samples`` and of
    ``uq.sobol``'s rows; ``index_vs_E``: the elasticity sweep (design, E_Pa, index_m and, for a
    pose, index_phi_rad) or None; ``paper``: {design: (index, minus, plus)} [m]; ``responses``:
    keys of ``RESPONSES``."""

    designs = _uq_designs(linear)
    cases = _uq_cases(linear)
    one = len(responses) == 1
    if one:
        fig, axes = plt.subplots(
            1,
            len(cases),
            figsize=(5 + 10 * len(cases) / 2, 5.8),
            gridspec_kw={"width_ratios": [2, 1][: len(cases)]},
            squeeze=False,
            layout="constrained",
        )
    else:
        fig, axes = plt.subplots(
            len(responses),
            len(cases),
            figsize=(4.5 + 3.5 * len(cases), 8.5),
            squeeze=False,
            layout="constrained",
        )
    colours = dict(zip(designs, OKABE_ITO))
    for i, key in enumerate(responses):
        r = RESPONSES[key]
        col, k = r["index"], r["scale"]
        for ax, case in zip(axes[i], cases):
            ticks, labels, x = [], [], 0.0
            for dk in designs:
                lin = linear.get((dk, case))
                if lin is None:
                    continue
                nominal = lin.loc[lin["sample"] == -1, col].iloc[0] * k
                vals = lin.loc[lin["sample"] >= 0, col].dropna().to_numpy() * k
                parts = ax.violinplot([vals], positions=[x], widths=0.7, showextrema=True, showmedians=True)
                _colour_violin(parts, colours[dk], 0.45)
                ax.plot([x - 0.35, x + 0.35], [nominal, nominal], "k:", lw=1)
                ticks.append(x)
                labels.append(f"{dk}\nper-cable E\nn = {len(vals)}")
                x += 1.0
                g = index_vs_E[index_vs_E.design == dk] if index_vs_E is not None else []
                if case == "uncompensated" and len(g) and col in g:
                    ax.vlines(x, g[col].min() * k, g[col].max() * k, color=colours[dk], lw=6, alpha=0.7)
                    ax.plot(x, nominal, "k_", ms=14)
                    ticks.append(x)
                    labels.append(f"{dk}\ncommon E\nours" if one else f"{dk}\ncommon E")
                    x += 1.0
                if case == "uncompensated" and index_vs_E is not None and key == "dp" and dk in paper:
                    mid, minus, plus = (v * 1e3 for v in paper[dk])
                    ax.vlines(x, mid - minus, mid + plus, color=colours[dk], lw=6, alpha=0.35, hatch="//")
                    ax.plot(x, mid, "k_", ms=14)
                    ticks.append(x)
                    labels.append(f"{dk}\ncommon E\npaper")
                    x += 1.0
                tol = tolerances.get((dk, case))
                if tol is not None and len(tol) and col in tol:
                    parts = ax.violinplot(
                        [tol[col].dropna().to_numpy() * k], positions=[x], widths=0.7, showextrema=True
                    )
                    _colour_violin(parts, colours[dk], 0.2)
                    ticks.append(x)
                    labels.append(f"{dk}\nall param.\nn = {len(tol)}")
                    x += 1.5
            ax.set_xticks(ticks, labels, fontsize=7)
            ax.set(
                xlabel="design and sampling [-]",
                ylabel=f"global index mean {r['label']} over RW_C [{r['unit']}]",
                title=case if one else f"{case}: {r['label']}",
            )
            ax.grid(alpha=0.3, axis="y")
    key = [Patch(color=colours[d], alpha=0.6, label=d) for d in designs] + [
        Line2D([], [], color="k", ls=":", label="nominal robot (dotted)"),
        Line2D([], [], color="0.4", lw=6, alpha=0.7, label="common-E band [min, max] (bar)"),
    ]
    if one:
        key.append(Line2D([], [], color="k", marker="_", ls="", ms=14, label="index at E_mean (tick)"))
    key.append(Patch(color="0.4", alpha=0.45, label="violin: samples; whiskers: min, median, max"))
    fig.legend(handles=key, loc="outside lower center", ncol=len(key) if one else 2, fontsize=7)
    if one:
        title = (
            f"Global index under per-cable moduli beside the common-E band (section 5.1){mode_suffix(mode)}"
        )
    else:
        title = f"Global indices of {_and(responses)} under per-cable moduli\n{mode_suffix(mode)[3:]}"
    fig.suptitle(title, fontsize=10)
    return save(fig, out)


def _and(responses):
    """'‖δp‖ and δφ': the labels of the responses."""
    return " and ".join(RESPONSES[k]["label"] for k in responses)


def uq_path_bands(bands, common, out, mode=None, common_mode=None, responses=("dp",)):
    """‖δp‖ (and δφ for a pose) along the section 5.2 path: 5-50-95 % band under per-cable moduli
    for each design (columns), uncompensated beside the common-E curves of the elasticity section
    and compensated (rows: case x response). ``bands``: {(design, case): ``uq.path_bands`` table};
    ``common``: {response: list of (design, E [Pa], s [m], value [m or rad])} of the common-E paths
    (Fig. 19), computed in ``common_mode`` (named in the legend when it differs from ``mode``)."""
    designs, cases = _uq_designs(bands), _uq_cases(bands)
    one = len(responses) == 1
    rows = [(case, key) for case in cases for key in responses]
    fig, axes = plt.subplots(
        len(rows),
        len(designs),
        figsize=(5.5 * len(designs), 3.8 * len(rows)) if one else (6.5 * len(designs), 3.6 * len(rows)),
        squeeze=False,
        layout="constrained",
    )
    Es = sorted({c[1] for c in common.get("dp", [])})
    styles = dict(zip(Es, [":", "-", "--"] if len(Es) == 3 else ["-"] * len(Es)))
    other = f" ({MODE_TITLES[common_mode].split(' (')[0]})" if common_mode and common_mode != mode else ""
    for dk, case, key, r, ax, b in _panels(axes, designs, rows, bands):
        k, q = r["scale"], r["q"]
        ax.fill_between(
            b.s,
            b[f"q05{q}"] * k,
            b[f"q95{q}"] * k,
            color=OKABE_ITO[0],
            alpha=0.3,
            label="5-95 % per-cable E",
        )
        ax.plot(b.s, b[f"q50{q}"] * k, color=OKABE_ITO[0], label="median per-cable E")
        ax.plot(b.s, b[r["nominal"]] * k, "k", lw=0.8, alpha=0.6, label="nominal")
        if case == "uncompensated":
            for d, E, s, v in common.get(key, []):
                if d == dk:
                    ax.plot(
                        s,
                        v * k,
                        styles.get(E, "-"),
                        color=OKABE_ITO[1],
                        lw=1,
                        label=f"common E = {E / 1e9:g} GPa{other}",
                    )
        ax.set(
            xlabel="position along the path s [m]",
            ylabel=f"{r['label']} [{r['unit']}]",
            title=f"{dk} {case}" if one else f"{dk} {case}: {r['label']}",
        )
        ax.grid(alpha=0.3)
        ax.legend(
            fontsize=6,
            loc="upper center",
            bbox_to_anchor=(0.5, -0.2 if one else -0.25),
            ncol=2,
            frameon=False,
        )
    if one:
        title = (
            f"‖δp‖ along the section 5.2 path under per-cable moduli (Fig. 19 extended){mode_suffix(mode)}"
        )
    else:
        title = (
            f"{_and(responses)} along the section 5.2 path under per-cable moduli\n{mode_suffix(mode)[3:]}"
        )
    fig.suptitle(title, fontsize=10)
    return save(fig, out)


def _sobol_top(tab):
    """Top of a Sobol panel's y axis: 1.05, raised to show the upper whiskers (index + 95 %
    interval) of the estimates that pass it, up to 1.5 (few base samples give wider intervals)."""
    if not len(tab):
        return 1.05
    whisker = max(float((tab.ST + tab.ST_conf).max()), float((tab.S1 + tab.get("S1_conf", 0)).max()))
    return float(min(1.5, max(1.05, whisker + 0.05)))


def uq_sobol(tab, out, mode=None, responses=("dp",)):
    """Sobol total (bars) and first-order (dots) indices of the global index of each response, both
    with their 95 % confidence intervals, per parameter group (left of each pair) and per parameter
    (right: each cable's E_i, d_i, h_i, r_p_i, anchor coordinates and the mass), for each design
    before and after compensation (rows: case x response)."""
    one = len(responses) == 1
    designs = list(dict.fromkeys(tab[tab.output == "index"].design))
    cases = [c for c in UQ_CASES if c in set(tab[tab.output == "index"].case)]
    rows = [(case, key) for case in cases for key in responses]
    if one:
        figsize = (6.5 * len(designs) + 1, 3.75 * len(cases) + 0.5 * (len(cases) == 1))
    else:
        figsize = (7.5 * len(designs) + 1, 3.4 * len(rows))
    fig, axes = plt.subplots(
        len(rows),
        2 * len(designs),
        figsize=figsize,
        squeeze=False,
        layout="constrained",
        gridspec_kw={"width_ratios": [1, 3] * len(designs)},
    )
    for j, dk in enumerate(designs):
        for i, (case, key) in enumerate(rows):
            r = RESPONSES[key]
            g = tab[(tab.output == r["output"]) & (tab.design == dk) & (tab.case == case)]
            # one y range per design, case and response (groups and parameters), intervals below -1 clipped
            lo = max(-1.0, min(0.0, float((g.S1 - g.get("S1_conf", 0)).min()) - 0.05)) if len(g) else 0.0
            for k, level in enumerate(("group", "parameter")):
                ax = axes[i, 2 * j + k]
                d = g[g.level == level]
                x = np.arange(len(d))
                ax.bar(
                    x, d.ST, yerr=d.ST_conf, color=OKABE_ITO[0], alpha=0.7, capsize=2, label="total ST ± 95 %"
                )
                ax.errorbar(
                    x,
                    d.S1,
                    yerr=d.S1_conf if "S1_conf" in d else None,
                    fmt="o",
                    color="k",
                    ms=3,
                    capsize=2,
                    label="first order S1 ± 95 %",
                )
                ax.axhline(0, color="0.5", lw=0.6)
                ax.set_xticks(
                    x,
                    d.name,
                    rotation=90 if level == "parameter" else 0,
                    fontsize=6 if level == "parameter" else 8,
                )
                what = "groups" if k == 0 else "per parameter"
                ax.set(
                    xlabel=f"{level} [-]",
                    ylabel="Sobol index [-]" if k == 0 else "",
                    title=f"{dk} {case}: {what}" if one else f"{dk} {case}, index of {r['label']}: {what}",
                    ylim=(lo, _sobol_top(g)),
                )
                ax.title.set_fontsize(8)
                ax.grid(alpha=0.3, axis="y")
                if k == 1:
                    ax.tick_params(labelleft=False)
    handles, names = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, names, loc="outside lower center", ncol=2, fontsize=7)
    if one:
        title = f"Which uncertainty drives the global index (SALib, Saltelli sampling){mode_suffix(mode)}"
    else:
        title = f"Which uncertainty drives the global indices of {_and(responses)} (SALib){mode_suffix(mode)}"
    fig.suptitle(title, fontsize=10)
    return save(fig, out)


def uq_dominant_map(maps, A, z, out, mode=None, responses=("dp",)):
    """The parameter whose first-order contribution to the spread of each response is the largest,
    on the plane z (columns: designs; rows: case x response); hatched where it explains less than
    half of the spread; points whose nominal robot's cables interfere at its solved pose (left out
    of the map, column ``interfering``) pink and crossed, counted in the panel's title.
    ``maps``: {(design, case): ``uq.dominant_map`` table}."""
    designs, cases = _uq_designs(maps), _uq_cases(maps)
    one = len(responses) == 1
    rows = [(case, key) for case in cases for key in responses]
    names = sorted(
        {
            n
            for df in maps.values()
            for key in responses
            for n in df[RESPONSES[key]["dominant"]].dropna().unique()
            if n
        }
    )
    cmap = plt.get_cmap("tab20", max(len(names), 1))
    code = {n: k for k, n in enumerate(names)}
    fig, axes = plt.subplots(
        len(rows),
        len(designs),
        figsize=(5 * len(designs) + 2, (4.75 if one else 4.0) * len(rows)),
        squeeze=False,
        layout="constrained",
    )
    for dk, case, key, r, ax, df in _panels(axes, designs, rows, maps):
        if not one:
            ax.set_facecolor(NOT_OK_COLOUR)
        val = df[r["dominant"]].map(lambda n: code.get(n, np.nan)).astype(float)
        xs, ys, Z = plane_grid(df, val.to_numpy())
        _, _, share = plane_grid(df, df[r["share"]].to_numpy())
        ax.pcolormesh(xs, ys, Z, cmap=cmap, vmin=-0.5, vmax=len(names) - 0.5, shading="nearest")
        if one or np.nanmin(np.where(np.isfinite(share), share, 1.0)) < 0.5:
            ax.contourf(
                xs,
                ys,
                np.where(share < 0.5, 1.0, np.nan),
                levels=[0.5, 1.5],
                colors="none",
                hatches=["///"],
            )
        bad = _interfering_cells(ax, df)
        draw_anchors(ax, A)
        if one:
            ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{dk} {case}{bad}", aspect="equal")
        else:
            title = f"{dk} {case}: spread of {r['label']}{bad}"
            ax.set(xlabel="x [m]", ylabel="y [m]", title=title, aspect="equal")
            ax.title.set_fontsize(9)
    handles = [Patch(color=cmap(code[n]), label=n) for n in names]
    fig.legend(handles=handles, loc="outside right center", fontsize=7, title="dominant")
    title = f"Dominant uncertain parameter at z = {z:g} m (hatched: < 50 %)"
    fig.suptitle(title + (mode_suffix(mode) if one else f"\n{mode_suffix(mode)[3:]}"), fontsize=10)
    return save(fig, out)


def uq_residual_map(maps, A, z, out, mode=None, responses=("dp",)):
    """What compensation leaves, on the plane z (beyond the paper): for each design (columns) and
    case the study ran, the nominal robot's ‖δp‖ (uncompensated: the pose error the paper studies;
    compensated: the round-trip residual of the compensated lengths, 0 up to rounding) and the
    first-order spread of ‖δp‖ under the declared parameters (RMS of the per-parameter
    contributions, ``uq.dominant_map``'s ``rms_m``), and the same of δφ for a pose. Rows: nominal
    then spread, per case and response; grey: not ok; pink and crossed, counted in the panel's
    title: left out because the nominal robot's cables interfere at its solved pose. ``maps``:
    {(design, case): ``uq.dominant_map`` table}."""
    designs, cases = _uq_designs(maps), _uq_cases(maps)
    one = len(responses) == 1
    rows = [(case, key, c) for case in cases for key in responses for c in ("nominal", "rms")]
    fig, axes = plt.subplots(
        len(rows),
        len(designs),
        figsize=(5 * len(designs) + 1.5, 4.4 * len(rows))
        if one
        else (6 * len(designs) + 1.5, 3.9 * len(rows)),
        squeeze=False,
        layout="constrained",
    )
    for i, (case, key, c) in enumerate(rows):
        r = RESPONSES[key]
        if one:
            what = (
                f"nominal robot {r['label']}"
                if c == "nominal"
                else f"spread of {r['label']} (RMS, declared parameters)"
            )
            bar = f"{what.split(' (')[0]} [{r['unit']}]"
        else:
            what = f"nominal robot {r['label']}" if c == "nominal" else f"spread of {r['label']} (RMS)"
            bar = f"{r['label']} [{r['unit']}]"
        for j, dk in enumerate(designs):
            ax = axes[i, j]
            df = maps.get((dk, case))
            if df is None:
                ax.set_visible(False)
                continue
            xs, ys, Z = plane_grid(df, df[r[c]].to_numpy() * r["scale"])
            ax.set_facecolor(NOT_OK_COLOUR)
            finite = Z[np.isfinite(Z)]
            top = float(np.abs(finite).max()) if finite.size else 0.0
            if top < 1e-6:  # the compensated nominal residual: zero up to rounding, stated
                grey = np.where(np.isfinite(Z), 0.0, np.nan)
                ax.pcolormesh(xs, ys, grey, cmap="Greys", vmin=0, vmax=1, shading="nearest")
                label = f"max {top:.1g} {r['unit']} (round trip)"
            else:
                levels = round_levels(float(finite.min()), float(finite.max()), 10)
                cf = ax.contourf(xs, ys, Z, levels=levels, cmap="viridis")
                fig.colorbar(cf, ax=ax, label=bar, shrink=0.8)
                label = f"{finite.min():.3g} to {finite.max():.3g} {r['unit']}"
            bad = _interfering_cells(ax, df)
            draw_anchors(ax, A)
            ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{dk} {case}: {what}\n{label}{bad}", aspect="equal")
            ax.title.set_fontsize(8)
    if one:
        title = f"What compensation leaves at z = {z:g} m (beyond the paper){mode_suffix(mode)}"
    else:
        title = f"What compensation leaves at z = {z:g} m\n{mode_suffix(mode)[3:]}"
    fig.suptitle(title, fontsize=10)
    return save(fig, out)


def uq_agreement(mc, out, mode=None, responses=("dp",)):
    """The global index of each response of each full-solve Monte Carlo sample against its
    linearised value, one panel per design and case (columns) and response (rows), with the line of
    equality."""
    keys = sorted(mc)
    one = len(responses) == 1
    fig, axes = plt.subplots(
        len(responses),
        len(keys),
        figsize=(3.8 * len(keys), 4.2) if one else (max(3.8 * len(keys), 7.0), 7.6),
        squeeze=False,
        layout="constrained",
    )
    for i, resp in enumerate(responses):
        r = RESPONSES[resp]
        for ax, key in zip(axes[i], keys):
            df, k = mc[key], r["scale"]
            ax.plot(df[r["full"]] * k, df[r["lin"]] * k, "o", ms=3, color=OKABE_ITO[0])
            lo = np.nanmin([df[r["full"]].min(), df[r["lin"]].min()]) * k
            hi = np.nanmax([df[r["full"]].max(), df[r["lin"]].max()]) * k
            ax.plot([lo, hi], [lo, hi], "k:", lw=1)
            ax.set(
                xlabel=f"full solves [{r['unit']}]",
                ylabel=f"linearised [{r['unit']}]",
                title=f"{key[0]}\n{key[1]}" if one else f"{key[0]} {key[1]}: index of {r['label']}",
            )
            ax.title.set_fontsize(9)
            ax.tick_params(axis="x", labelrotation=30, labelsize=7)
            ax.grid(alpha=0.3)
    if one:
        title = f"Global index per sample: linearised against full solves{mode_suffix(mode)}"
    else:
        title = f"Global indices per sample: linearised against full solves\n{mode_suffix(mode)[3:]}"
    fig.suptitle(title, fontsize=10)
    return save(fig, out)
