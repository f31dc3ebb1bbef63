"""The figures of the design of experiments (Paty 2021 section 4.2, the study's ``doe`` part): the
global index of each test (Fig. 15) and the effects and interactions of the factors (Fig. 16).
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from cdpr.pipeline.plots.style import (
    DPHI_SCALE,
    DPHI_UNIT,
    KIND_COLOURS,
    OKABE_ITO,
    mode_suffix,
    paper_value,
    save,
)


def fig15_doe(tests, out, mode=None, paper=True):
    """Paty 2021 Fig. 15: the global index of each DOE test (Table 2), the factor levels of each
    test in a table under the bars, the paper's best and worst index (0.05 / 0.29 m) as markers
    (``paper``: False for a robot the paper did not study). With a column ``index_phi_rad`` (a rigid
    platform) the orientation index of each test in a second panel."""
    spatial = "index_phi_rad" in tests
    fig, axes = plt.subplots(
        1, 2 if spatial else 1, figsize=(15 if spatial else 8, 4.8), squeeze=False, layout="constrained"
    )
    ax = axes[0, 0]
    x = np.arange(len(tests))
    colours = [KIND_COLOURS.get(k) for k in tests.kind]
    ax.bar(x, tests.index_m * 1e3, color=colours)
    ax.set_xticks(x, [f"T{t}" for t in tests.test])
    if spatial:
        a = axes[0, 1]
        a.bar(x, tests.index_phi_rad * DPHI_SCALE, color=colours)
        a.set_xticks(x, [f"T{t}" for t in tests.test])
        a.set(
            xlabel="DOE test [Table 2]",
            ylabel=f"orientation index mean δφ [{DPHI_UNIT}]",
            title=f"DOE responses: orientation{mode_suffix(mode)}",
        )
        a.grid(axis="y", alpha=0.3)
    for name, q in (("paper's best", "DOE minimum (test 1)"), ("paper's worst", "DOE maximum (test 7)")):
        if not paper:
            break
        v = paper_value(q)
        if v is not None:
            ax.axhline(v * 1e3, color="r", ls="--", lw=0.9)
            ax.annotate(
                f"{name} {v:g} m",
                (1.0, v * 1e3),
                xycoords=("axes fraction", "data"),
                xytext=(3, 0),
                textcoords="offset points",
                fontsize=7,
                color="r",
                va="center",
            )
    cells = [
        list(tests.kind),
        [f"{h * 1e3:g}" for h in tests.h_m],
        [f"{r * 1e3:g}" for r in tests.r_p_m],
    ]
    tb = ax.table(
        cellText=cells,
        rowLabels=["joint", "h [mm]", "r_p [mm]"],
        loc="bottom",
        cellLoc="center",
        bbox=[0, -0.32, 1, 0.22],
    )
    tb.set_fontsize(7)
    ax.set(
        xlabel="DOE test [Table 2]",
        ylabel="global index mean ‖δp‖ [mm]",
        title=f"DOE responses (Fig. 15){mode_suffix(mode)}",
    )
    ax.xaxis.set_label_position("top")
    ax.grid(axis="y", alpha=0.3)
    return save(fig, out)


def fig16_effects(eff, out, mode=None):
    """Paty 2021 Fig. 16: effects and interactions of the coded factors on the global index; the
    effect of a term is 2 × its regression coefficient (the change from its -1 to its +1 level).
    Colour-blind-safe signs (blue: lowers the index, vermillion: raises it). A table with a column
    ``response`` (a rigid platform: ``index_m`` and ``index_phi_rad``) gets one panel per response,
    the orientation's in mrad."""
    responses = list(dict.fromkeys(eff.response)) if "response" in eff else ["index_m"]
    fig, axes = plt.subplots(
        1, len(responses), figsize=(7 * len(responses), 4.4), squeeze=False, layout="constrained"
    )
    for ax, resp in zip(axes[0], responses):
        e = eff[eff.term != "mean"]
        if "response" in eff:
            e = e[e.response == resp]
        phi = resp == "index_phi_rad"
        ax.bar(
            np.arange(len(e)),
            e.effect * (DPHI_SCALE if phi else 1e3),
            color=[OKABE_ITO[0] if v < 0 else OKABE_ITO[1] for v in e.effect],
        )
        ax.set_xticks(np.arange(len(e)), e.term, rotation=30, ha="right")
        ax.axhline(0.0, color="k", lw=0.8)
        ax.set(
            xlabel="term [coded factors -1/+1: joint SR/DR, h and r_p low/high of Table 2]",
            ylabel=f"effect = 2 × coefficient [{DPHI_UNIT if phi else 'mm'}]",
            title=f"Effects and interactions on mean {'δφ' if phi else '‖δp‖'} (Fig. 16){mode_suffix(mode)}",
        )
        ax.title.set_fontsize(9)
        ax.grid(axis="y", alpha=0.3)
    return save(fig, out)
