"""The figure of the (r_p, h) maps (Paty 2021 section 4.3, the study's ``maps`` part): the global
index over the plane of the pulley dimensions with the valley, the fitted and the paper's lines and
optima (Fig. 17).
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from cdpr.pipeline.plots.style import DPHI_SCALE, DPHI_UNIT, mode_suffix, round_levels, save

#: The paper's lines h = k r_p (Paty 2021 section 4.3: D_SR h = 40/13 r_p, D_DR h = 5/4 r_p) and
#: optimal designs (Table 3: SR* h = 107.7 mm, r_p = 35 mm; DR* h = 100 mm, r_p = 80 mm) [m].
PAPER_LINES = {"SR": 40.0 / 13.0, "DR": 5.0 / 4.0}
PAPER_OPTIMA = {"SR": (0.1077, 0.035), "DR": (0.100, 0.080)}


def fig17_maps(tab, valleys, lines, tests, levels, out, mode=None, paper=True):
    """Paty 2021 Fig. 17: the global index over the (r_p, h) plane for each pulley kind on one
    colour range with labelled contour lines, the valley r_p*(h), the fitted line h = k r_p and
    our optimum I, the paper's line D and its optimum (SR*, DR*) (``paper``: False for a robot the
    paper did not study), the DOE field and tests T1-T8. ``valleys`` maps a kind to its valley
    table; ``lines`` has one row per kind. With a column ``index_phi_rad`` (a rigid platform) a
    second row maps the orientation index [mrad] with the DOE field."""
    kinds = list(dict.fromkeys(tab.kind))
    lo, hi = float(tab.index_m.min()) * 1e3, float(tab.index_m.max()) * 1e3
    lv = round_levels(lo, hi, 20)
    spatial = "index_phi_rad" in tab
    fig, axes = plt.subplots(
        2 if spatial else 1,
        len(kinds),
        figsize=(6.0 * len(kinds) + 1.2, 11.6 if spatial else 5.8),
        squeeze=False,
        layout="constrained",
    )
    if spatial:
        _maps_dphi_row(fig, axes[1], tab, kinds, levels)
    cf = None
    for ax, kind in zip(axes[0], kinds):
        g = tab[tab.kind == kind]
        piv = g.pivot(index="h_m", columns="r_p_m", values="index_m")
        if piv.shape[0] > 1 and piv.shape[1] > 1 and lv is not None:
            cf = ax.contourf(piv.columns * 1e3, piv.index * 1e3, piv.values * 1e3, levels=lv, cmap="viridis")
            ax.contour(
                piv.columns * 1e3,
                piv.index * 1e3,
                piv.values * 1e3,
                levels=lv[::4],
                colors="k",
                linewidths=0.4,
            )  # unlabelled: the colour bar's ticks are these levels (labels would sit on T1-T8)
        v = valleys[kind]
        ax.plot(v.r_p_star * 1e3, v.h * 1e3, "wo", ms=3, mec="k", mew=0.4, label="valley r_p*(h)")
        line = lines[lines.kind == kind].iloc[0]
        rmax = g.r_p_m.max()
        rr = np.linspace(0, rmax, 10)
        if np.isfinite(line.slope_k):
            ax.plot(rr * 1e3, line.slope_k * rr * 1e3, "r-", label=f"ours: h = {line.slope_k:.2f} r_p")
        if paper and kind in PAPER_LINES:
            k = PAPER_LINES[kind]
            ax.plot(rr * 1e3, k * rr * 1e3, color="m", ls="--", label=f"paper D_{kind}: h = {k:.3g} r_p")
            h_p, r_p = PAPER_OPTIMA[kind]
            ax.plot(r_p * 1e3, h_p * 1e3, "D", color="m", mec="w", ms=8, zorder=6, label=f"paper {kind}*")
        r0, r1 = levels["r_p_m"]
        h0, h1 = levels["h_m"]
        ax.add_patch(
            plt.Rectangle((r0 * 1e3, h0 * 1e3), (r1 - r0) * 1e3, (h1 - h0) * 1e3, fill=False, ec="w", ls="--")
        )
        for t in tests[tests.kind == kind].itertuples():
            ax.plot(t.r_p_m * 1e3, t.h_m * 1e3, "w+", ms=6, mew=1.2)  # the test's point; its name beside it
            ax.annotate(
                f"T{t.test}",
                (t.r_p_m * 1e3, t.h_m * 1e3),
                xytext=(-9, -9),
                textcoords="offset points",
                color="w",
                fontsize=7,
                ha="center",
                va="center",
                bbox=dict(boxstyle="round,pad=0.15", fc="k", alpha=0.6),
            )
        if line.r_p_opt_m == line.r_p_opt_m and line.r_p_opt_m is not None:
            ax.plot(
                line.r_p_opt_m * 1e3,
                line.h_opt_m * 1e3,
                "r*",
                ms=13,
                mec="w",
                zorder=7,
                label=f"ours: I_{kind}",
            )
        hmax = max(g.h_m.max(), h1) * 1e3
        ax.set(
            xlabel="sheave radius r_p [mm]",
            ylabel="lever arm h [mm]",
            title=f"{kind} pulleys (Fig. 17)",
            xlim=(0, rmax * 1e3),
            ylim=(0, hmax * 1.08),
        )
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, frameon=False)
    if cf is not None:
        cb = fig.colorbar(
            cf, ax=axes[0].tolist(), label="global index mean ‖δp‖ [mm] (black lines at the ticks)"
        )
        cb.set_ticks(lv[::4])
    fig.suptitle(f"Global index over the (r_p, h) plane{mode_suffix(mode)}", fontsize=10)
    return save(fig, out)


def _maps_dphi_row(fig, axes, tab, kinds, levels):
    """The orientation index [mrad] over the (r_p, h) plane, one panel per kind on one colour range,
    with the DOE field (dashed): the second row of ``fig17_maps`` for a rigid platform."""
    v = tab.index_phi_rad * DPHI_SCALE
    lv = round_levels(float(v.min()), float(v.max()), 16)
    cf = None
    for ax, kind in zip(axes, kinds):
        g = tab[tab.kind == kind]
        piv = g.pivot(index="h_m", columns="r_p_m", values="index_phi_rad")
        if piv.shape[0] > 1 and piv.shape[1] > 1 and lv is not None and len(lv) > 1:
            cf = ax.contourf(
                piv.columns * 1e3, piv.index * 1e3, piv.values * DPHI_SCALE, levels=lv, cmap="magma"
            )
        ax.plot(g.r_p_m * 1e3, g.h_m * 1e3, "k.", ms=3)
        r0, r1 = levels["r_p_m"]
        h0, h1 = levels["h_m"]
        ax.add_patch(
            plt.Rectangle((r0 * 1e3, h0 * 1e3), (r1 - r0) * 1e3, (h1 - h0) * 1e3, fill=False, ec="c", ls="--")
        )
        ax.set(
            xlabel="sheave radius r_p [mm]",
            ylabel="lever arm h [mm]",
            title=f"{kind} pulleys: orientation index mean δφ",
            xlim=(0, g.r_p_m.max() * 1e3),
            ylim=(0, max(g.h_m.max(), h1) * 1e3 * 1.08),
        )
    if cf is not None:
        fig.colorbar(cf, ax=list(axes), label=f"orientation index mean δφ [{DPHI_UNIT}]")
