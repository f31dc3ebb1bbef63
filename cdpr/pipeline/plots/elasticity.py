"""The figures of the cable elasticity (Paty 2021 section 5, the study's ``elasticity`` part): the
global index of each optimal design versus Young's modulus (Fig. 18) and ‖δp‖ along the section 5.2
path at E_min, E_mean, E_max with the crossings (Fig. 19).
"""

from __future__ import annotations

import matplotlib.pyplot as plt

from cdpr.pipeline.plots.style import DPHI_LABEL, DPHI_SCALE, DPHI_UNIT, OKABE_ITO, mode_suffix, save


def fig18_index_vs_E(tab, E_mean, bands, out, mode=None, paper=None):
    """Paty 2021 Fig. 18: the global index of each optimal design versus Young's modulus, with the
    nominal modulus E_mean and our band [min, max] over the range shaded; ``paper`` {design:
    (index, minus, plus)} [m] draws the paper's band as an error bar at E_mean."""
    paper = paper or {}
    spatial = "index_phi_rad" in tab
    fig, axes = plt.subplots(
        1, 2 if spatial else 1, figsize=(15 if spatial else 7.5, 4.6), squeeze=False, layout="constrained"
    )
    ax = axes[0, 0]
    if spatial:  # a rigid platform: the orientation index versus E beside it
        a = axes[0, 1]
        for i, (dk, g) in enumerate(tab.groupby("design", sort=False)):
            c = OKABE_ITO[i % len(OKABE_ITO)]
            a.plot(g.E_Pa / 1e9, g.index_phi_rad * DPHI_SCALE, "o-", ms=3, color=c, label=f"{dk} (ours)")
            a.axhspan(
                g.index_phi_rad.min() * DPHI_SCALE, g.index_phi_rad.max() * DPHI_SCALE, color=c, alpha=0.12
            )
        a.axvline(E_mean / 1e9, color="k", ls=":", label=f"E_mean = {E_mean / 1e9:g} GPa")
        a.set(
            xlabel="Young's modulus E [GPa]",
            ylabel=f"orientation index mean δφ [{DPHI_UNIT}]",
            title=f"Orientation index versus E, shaded: our band{mode_suffix(mode)}",
        )
        a.title.set_fontsize(9)
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    for i, (dk, g) in enumerate(tab.groupby("design", sort=False)):
        c = OKABE_ITO[i % len(OKABE_ITO)]
        ax.plot(g.E_Pa / 1e9, g.index_m * 1e3, "o-", ms=3, color=c, label=f"{dk} (ours)")
        b = bands[bands.design == dk].iloc[0]
        ax.axhspan(b.index_min_m * 1e3, b.index_max_m * 1e3, color=c, alpha=0.12)
        if dk in paper:
            mid, minus, plus = (v * 1e3 for v in paper[dk])
            ax.errorbar(
                [E_mean / 1e9 + 1.5],
                [mid],
                yerr=[[minus], [plus]],
                fmt="s",
                color=c,
                mfc="w",
                capsize=4,
                label=f"{dk}: paper {mid:g} +{plus:g}/-{minus:g} mm",
            )
    ax.axvline(E_mean / 1e9, color="k", ls=":", label=f"E_mean = {E_mean / 1e9:g} GPa")
    ax.set(
        xlabel="Young's modulus E [GPa]",
        ylabel="global index mean ‖δp‖ [mm]",
        title=f"Index versus E (Fig. 18), shaded: our band{mode_suffix(mode)}",
    )
    ax.title.set_fontsize(9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    return save(fig, out)


def fig19_paths(curves, crossings, out, mode=None, paper=None, phi=None):
    """Paty 2021 Fig. 19: ‖δp‖ along the section 5.2 path for each design (colour) at E_min,
    E_mean, E_max (line style), with our crossings of the E_max and E_min curves (solid vertical
    lines) and the paper's (``paper`` {design: s [m]}, dashed). ``curves`` is a list of (design, E
    [Pa], s [m], dp [m]); ``crossings`` a table design, s_m. ``phi``: the same list with δφ [rad]
    (a rigid platform), drawn in a second panel [mrad]."""
    paper = paper or {}
    fig, axes = plt.subplots(
        2 if phi else 1, 1, figsize=(7.5, 8.6 if phi else 4.6), squeeze=False, layout="constrained"
    )
    ax = axes[0, 0]
    designs = list(dict.fromkeys(c[0] for c in curves))
    Es = sorted({c[1] for c in curves})
    styles = dict(zip(Es, [":", "-", "--"] if len(Es) == 3 else ["-"] * len(Es)))
    colours = dict(zip(designs, OKABE_ITO))
    if phi:
        a = axes[1, 0]
        for dk, E, s, v in phi:
            a.plot(
                s,
                v * DPHI_SCALE,
                styles.get(E, "-"),
                color=colours.get(dk),
                label=f"{dk} E = {E / 1e9:g} GPa",
            )
        a.set(
            xlabel="position along the path s [m]",
            ylabel=DPHI_LABEL,
            title=f"δφ along the path at E_min, E_mean, E_max{mode_suffix(mode)}",
        )
        a.title.set_fontsize(9)
        a.grid(alpha=0.3)
        a.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    for dk, E, s, dp in curves:
        ax.plot(s, dp * 1e3, styles[E], color=colours[dk], label=f"{dk} E = {E / 1e9:g} GPa")
    for r in crossings.itertuples():
        ax.axvline(r.s_m, color=colours.get(r.design, "k"), lw=1.0, alpha=0.8)
    for dk, s in paper.items():
        if dk in colours and s is not None:
            ax.axvline(s, color=colours[dk], lw=1.0, ls=(0, (5, 3)))
    ours = ", ".join(f"{r.design} {r.s_m:.2f} m" for r in crossings.itertuples()) or "none"
    theirs = ", ".join(f"{d} {s:g} m" for d, s in paper.items()) or "not given"
    ax.set(
        xlabel=f"position along the path s [m]\ncrossings E_max/E_min, solid: ours ({ours}); dashed: paper ({theirs})",
        ylabel="‖δp‖ [mm]",
        title=f"‖δp‖ along the section 5.2 path (Fig. 19){mode_suffix(mode)}",
    )
    ax.xaxis.label.set_fontsize(8)
    ax.title.set_fontsize(9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    return save(fig, out)
