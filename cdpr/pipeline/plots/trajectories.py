"""The figures of the paths (Paty 2021 section 3.3.1, the study's ``trajectories`` part): ‖δp‖ (and
δφ, the tensions) along each path with a status strip (Fig. 10), and the min and max along each
path (Fig. 11).
"""

from __future__ import annotations

import re

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.patches import Patch

from cdpr.pipeline.plots.style import DPHI_LABEL, DPHI_SCALE, KIND_COLOURS, OKABE_ITO, mode_suffix, save

#: Colours of the point statuses in the status strips (ok is not drawn).
STATUS_COLOURS = {
    "ok": "white",
    "slack": OKABE_ITO[1],
    "over_tension": OKABE_ITO[3],
    "inaccessible": "0.35",
    "not_converged": OKABE_ITO[4],
}


def fig10_trajectories(tables, minmax, out, mode=None):
    """Paty 2021 Fig. 10: ‖δp‖ along the section 3.3.1 paths, one panel per robot (colour: pulley
    kind). ``tables`` maps a design label (robot_pulley) to its path table (s, dp, status);
    ``minmax`` has ok_until_s_m and path_length_m per design. Points that are not ok are not drawn
    as curves (no ‖δp‖ = 0 that reads as no error): a status strip under each panel shows, per
    design, where the points are ok or why they are not, and the legend gives each design's reach
    (the last ok point over the path length)."""

    robots = list(dict.fromkeys(lab.split("_", 1)[0] for lab in tables))
    per = {rk: [lab for lab in tables if lab.split("_", 1)[0] == rk] for rk in robots}
    n_strip = max(len(v) for v in per.values())
    # a rigid platform (tables with dphi): δφ and the cable tensions in panels under ‖δp‖
    spatial = any("dphi" in df for df in tables.values())
    extra = [2.6, 2.6] if spatial else []
    fig = plt.figure(figsize=(6.2 * len(robots), 5.4 + 2.6 * len(extra)), layout="constrained")
    outer = fig.add_gridspec(2 + len(extra), len(robots), height_ratios=[4, *extra, 0.35 * n_strip + 0.4])
    states = list(STATUS_COLOURS)
    cmap = ListedColormap([STATUS_COLOURS[s] for s in states])
    mm = minmax.set_index("design")
    seen = set()
    for j, rk in enumerate(robots):
        ax = fig.add_subplot(outer[0, j])
        strip = fig.add_subplot(outer[1 + len(extra), j], sharex=ax)
        if spatial:
            _path_dphi_tensions(
                fig.add_subplot(outer[1, j], sharex=ax),
                fig.add_subplot(outer[2, j], sharex=ax),
                {lab: tables[lab] for lab in per[rk]},
                rk,
            )
        for lab in per[rk]:
            df = tables[lab]
            ok = df.status == "ok"
            kind = lab.split("_", 1)[1] if "_" in lab else lab
            row = mm.loc[lab]
            reach = f"last ok point at s = {row.ok_until_s_m:.2f} of {row.path_length_m:.2f} m"
            ax.plot(
                df.s.where(ok), df.dp.where(ok) * 1e3, color=KIND_COLOURS.get(kind), label=f"{lab}: {reach}"
            )
            seen |= set(df.status.unique())
        codes = np.array(
            [[states.index(s) if s in states else 0 for s in tables[lab].status] for lab in per[rk]], float
        )
        s0 = tables[per[rk][0]].s.to_numpy()
        strip.pcolormesh(
            s0,
            np.arange(len(per[rk])),
            codes,
            cmap=cmap,
            vmin=-0.5,
            vmax=len(states) - 0.5,
            shading="nearest",
        )
        strip.set_yticks(np.arange(len(per[rk])), [lab.split("_", 1)[1] for lab in per[rk]], fontsize=7)
        strip.set(xlabel="position along the path s [m]", ylabel="status [-]")
        ax.tick_params(labelbottom=False)
        ax.set(
            ylabel="‖δp‖ [mm]", title=f"{rk}: ‖δp‖ along the {'path' if spatial else 'section 3.3.1 path'}"
        )
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.02 - 0.09 * n_strip), frameon=False)
        ax.set_ylim(bottom=0)
    handles = [Patch(facecolor=STATUS_COLOURS[s], edgecolor="0.5", label=s) for s in states if s in seen]
    fig.legend(
        handles=handles,
        loc="outside lower center",
        ncol=len(handles),
        fontsize=7,
        title="status strip",
        title_fontsize=7,
    )
    what = "‖δp‖, δφ and the tensions" if spatial else "‖δp‖"
    fig.suptitle(f"{what} along the paths (Fig. 10){mode_suffix(mode)}", fontsize=10)
    return save(fig, out)


def _tension_columns(df):
    """The tension columns t1..tm of a point table, in cable order."""
    return sorted((c for c in df.columns if re.fullmatch(r"t\d+", c)), key=lambda c: int(c[1:]))


def _path_dphi_tensions(ax_phi, ax_t, tables, name):
    """δφ [mrad] (``ax_phi``) and the least and largest cable tension [N] (``ax_t``, a slack cable
    at 0 N) along the path tables ``tables`` (label -> table with s, dphi, t1..tm, status), ok
    points only, one colour per pulley kind."""
    for lab, df in tables.items():
        ok = df.status == "ok"
        kind = lab.split("_", 1)[1] if "_" in lab else lab
        c = KIND_COLOURS.get(kind)
        if "dphi" in df:
            ax_phi.plot(df.s.where(ok), df["dphi"].where(ok) * DPHI_SCALE, color=c, label=lab)
        tt = df[_tension_columns(df)].fillna(0.0)
        ax_t.plot(df.s.where(ok), tt.max(axis=1).where(ok), color=c, label=f"{lab}: largest t_i")
        ax_t.plot(df.s.where(ok), tt.min(axis=1).where(ok), color=c, ls="--", label=f"{lab}: least t_i")
    ax_phi.set(ylabel=DPHI_LABEL, title=f"{name}: orientation error δφ")
    ax_phi.set_ylim(bottom=0)
    ax_t.set(ylabel="cable tension [N]", title=f"{name}: largest and least cable tension (slack: 0 N)")
    for a in (ax_phi, ax_t):
        a.tick_params(labelbottom=False)
        a.grid(alpha=0.3)
        a.title.set_fontsize(9)
    ax_phi.legend(fontsize=7)
    ax_t.legend(fontsize=6, ncol=2)


def fig11_minmax(minmax, out, mode=None):
    """Paty 2021 Fig. 11: min and max ‖δp‖ along each path, per design (table ``minmax``); with
    columns dphi_min_rad, dphi_max_rad (a rigid platform) the same for δφ in a second panel."""
    spatial = "dphi_max_rad" in minmax
    fig, axes = plt.subplots(
        1, 2 if spatial else 1, figsize=(13 if spatial else 6.5, 4.4), squeeze=False, layout="constrained"
    )
    ax = axes[0, 0]
    x = np.arange(len(minmax))
    if spatial:
        a = axes[0, 1]
        a.bar(
            x - 0.2, minmax.dphi_min_rad * DPHI_SCALE, 0.4, color=OKABE_ITO[0], label="min over the ok points"
        )
        a.bar(
            x + 0.2, minmax.dphi_max_rad * DPHI_SCALE, 0.4, color=OKABE_ITO[1], label="max over the ok points"
        )
        a.set_xticks(x, minmax.design, rotation=30, ha="right")
        a.set(
            xlabel="design [path_pulley]",
            ylabel=DPHI_LABEL,
            title=f"Min and max of δφ along the paths{mode_suffix(mode)}",
        )
        a.title.set_fontsize(9)
        a.grid(axis="y", alpha=0.3)
        a.legend(fontsize=8)
    ax.bar(x - 0.2, minmax.dp_min_m * 1e3, 0.4, color=OKABE_ITO[0], label="min over the ok points")
    ax.bar(x + 0.2, minmax.dp_max_m * 1e3, 0.4, color=OKABE_ITO[1], label="max over the ok points")
    ax.set_xticks(x, minmax.design, rotation=30, ha="right")
    ax.set(
        xlabel="design [robot_pulley]",
        ylabel="‖δp‖ [mm]",
        title=f"Min and max of ‖δp‖ along the paths (Fig. 11){mode_suffix(mode)}",
    )
    ax.title.set_fontsize(9)
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=8)
    return save(fig, out)
