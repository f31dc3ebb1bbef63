"""The figure of the dead length d (the study's ``dead_length`` part, not in the paper): the
paper-comparable numbers versus d, beside the paper's values when the study compares with the paper
(``paper_comparison: true``; on another robot the paper's CDPR4 values would mislead).
"""

from __future__ import annotations

import matplotlib.pyplot as plt

from cdpr.pipeline.plots.style import KIND_COLOURS, OKABE_ITO, mode_suffix, paper_value, save


def dead_length_figure(tab, d_default, out, mode=None, paper=True):
    """Sensitivity of the paper-comparable numbers to the dead length d (not given by the paper):
    the study robot's plane extremes (left) and the optimal designs' index at E_mean (right), with
    the paper's CDPR4 values as horizontal lines of the same colour (dash-dot) only when ``paper``
    (the study's ``paper_comparison``).

    Parameters
    ----------
    tab : DataFrame
        The dead-length sweep (d_m, plane_<kind>_<min|max>_m, <design>_Emean_index_m).
    d_default : float [m]
        The study's dead length, a vertical line.
    out : path
        The PNG (its PDF beside it).
    mode : str, optional
        The redundancy mode, for the title.
    paper : bool
        Draw the paper's values (default True; False for a study that does not compare with the paper).

    Returns
    -------
    list of Path
        The files written (``style.save``).
    """
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.8), layout="constrained")
    for c in [c for c in tab.columns if c.startswith("plane_")]:
        _, pk, stat, _ = c.split("_")
        col = KIND_COLOURS.get(pk)
        a.plot(
            tab.d_m,
            tab[c] * 1e3,
            "-" if stat == "max" else "--",
            marker="o",
            ms=3,
            color=col,
            label=f"{pk} plane {stat}",
        )
        v = paper_value(f"CDPR4_{pk} plane {stat}") if paper else None
        if v is not None:
            a.axhline(v * 1e3, color=col, ls="-.", lw=0.8, label=f"paper {pk} plane {stat} {v * 1e3:g} mm")
    for i, c in enumerate([c for c in tab.columns if c.endswith("_index_m") and "_Emean_" in c]):
        dk = c.split("_")[0]
        col = OKABE_ITO[i % len(OKABE_ITO)]
        b.plot(tab.d_m, tab[c] * 1e3, marker="o", ms=3, color=col, label=f"{dk} index at E_mean")
        v = paper_value(f"{dk.replace('opt', '*')} index (Table 3)") if paper else None
        if v is not None:
            b.axhline(v, color=col, ls="-.", lw=0.8, label=f"paper {dk.replace('opt', '*')} {v:g} mm")
    for ax, yl in ((a, "‖δp‖ on the plane [mm]"), (b, "global index mean ‖δp‖ [mm]")):
        ax.axvline(d_default, color="k", ls=":", label=f"default d = {d_default:g} m")
        ax.set(xlabel="dead length d [m]", ylabel=yl)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)
    fig.suptitle(
        f"Sensitivity of paper-comparable numbers to the dead length d{mode_suffix(mode)}", fontsize=10
    )
    return save(fig, out)
