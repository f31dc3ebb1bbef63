"""The figures of the error budget (pulley geometry, cable elasticity, winch exit point; beyond both
papers): the budget per design and along the paths.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from cdpr.pipeline.plots.style import OKABE_ITO, save

#: Colours of the error budget's effects (Okabe & Ito, colour-blind safe).
EFFECT_COLOURS = {
    "pulley": OKABE_ITO[0],
    "elasticity": OKABE_ITO[2],
    "winch": OKABE_ITO[1],
    "sag": OKABE_ITO[3],
    "interaction": "0.6",
    "all": "k",
}


def entry_colour(entry):
    """The colour of a budget entry, the same in every panel: an effect's own colour
    (``EFFECT_COLOURS``), and the error left after compensating it (``compensated_<effect>``, drawn
    hatched) in that effect's colour too.

    Parameters
    ----------
    entry : str
        A budget entry (``pulley``, ..., ``all``, ``compensated_<effect>``, ``neglected_sag``).

    Returns
    -------
    str
        A matplotlib colour.
    """
    return EFFECT_COLOURS[entry.removeprefix("compensated_").removeprefix("neglected_")]


def budget_bars(tab, out, xlabel="design [robot_pulley]"):
    """Error budget per design over RW_C: (a) stacked bars of each effect's share of the mean
    all-effects error (projection on its direction, so the stack sums to the mean ‖δp_all‖, marked
    by a black tick; negative shares go below zero), beside the mean ‖δp‖ of each effect alone;
    (b) the mean error left after compensating each effect, and all of them (exactly zero: written
    as text over its place, a log axis cannot draw it); (c), when the table has ``mean_rad`` (a
    rigid platform), the mean orientation error ‖δφ‖ of each effect alone, all together, the
    interaction and after compensating each. One colour per effect in every panel (``entry_colour``:
    the error left after compensating an effect is that effect's colour, hatched; all effects
    black). With heavy cables (a ``sag`` entry) sag is a fourth effect in every panel and (b) adds
    what sag adds under the massless compensated lengths. ``tab`` is the budget table (design, region, entry,
    mean_m, share_m, ...); rows of region RW_C are drawn. Legends sit outside."""
    t = tab[tab.region == "RW_C"]
    designs = list(dict.fromkeys(t.design))
    effects = _effects(t)
    x = np.arange(len(designs))
    get = lambda d, e, c: float(t[(t.design == d) & (t.entry == e)][c].iloc[0]) * 1e3  # noqa: E731
    if "mean_rad" in t:
        fig, (a, b, c) = plt.subplots(1, 3, figsize=(max(16, 3.6 * len(designs)), 5.6), layout="constrained")
    else:
        fig, (a, b) = plt.subplots(1, 2, figsize=(max(11, 2.6 * len(designs)), 5.6), layout="constrained")
    pos, neg = np.zeros(len(designs)), np.zeros(len(designs))
    for e in (*effects, "interaction"):
        v = np.array([get(d, e, "share_m") for d in designs])
        base = np.where(v >= 0, pos, neg)
        a.bar(x - 0.2, v, 0.38, bottom=base, color=EFFECT_COLOURS[e], label=f"{e} (share)")
        pos, neg = np.where(v >= 0, pos + v, pos), np.where(v < 0, neg + v, neg)
    tot = np.array([get(d, "all", "mean_m") for d in designs])
    a.scatter(x - 0.2, tot, marker="_", s=400, color="k", zorder=3, label="mean ‖δp_all‖")
    bottom = np.zeros(len(designs))
    for e in effects:
        v = np.array([get(d, e, "mean_m") for d in designs])
        a.bar(
            x + 0.2,
            v,
            0.38,
            bottom=bottom,
            color=EFFECT_COLOURS[e],
            alpha=0.45,
            hatch="//",
            label=f"{e} alone (hatched)",
        )
        bottom += v
    a.axhline(0, color="0.5", lw=0.8)
    a.set_xticks(x, designs, rotation=20)
    a.set(
        xlabel=xlabel,
        ylabel="mean ‖δp‖ [mm]",
        title="(a) shares of ‖δp_all‖ (left bar), each effect alone (right)",
    )
    a.title.set_fontsize(9)
    a.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=3, frameon=False)
    entries = ["all", *(f"compensated_{e}" for e in effects), "compensated_all"]
    if "sag" in effects:  # what sag adds under the massless compensated lengths
        entries.insert(-1, "neglected_sag")
    w = 0.8 / len(entries)
    zero_label = False
    for i, e in enumerate(entries):
        v = np.array([get(d, e, "mean_m") for d in designs])
        xe = x - 0.4 + (i + 0.5) * w
        hatch = "//" if e.startswith("compensated_") else None  # hatched: the error left after compensating
        b.bar(
            xe,
            v,
            w,
            color=entry_colour(e),
            hatch=hatch,
            edgecolor="w" if hatch else None,
            label=_entry_label(e),
        )
        for xx, vv in zip(xe, v):
            if vv == 0.0:
                b.annotate("0", (xx, 1e-3), ha="center", va="bottom", fontsize=7, color=entry_colour(e))
                zero_label = True
    b.set_xticks(x, designs, rotation=20)
    b.set_yscale("symlog", linthresh=1e-3)
    b.set(
        xlabel=xlabel,
        ylabel="mean ‖δp‖ [mm]",
        title="(b) error left after compensating" + (" ('0': exactly zero)" if zero_label else ""),
    )
    b.title.set_fontsize(9)
    b.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=3, frameon=False)
    if "mean_rad" in t:
        phi = [*effects, "interaction", "all", *entries[1:]]
        w = 0.8 / len(phi)
        for i, e in enumerate(phi):
            v = np.array([get(d, e, "mean_rad") for d in designs])
            colour = entry_colour(e)  # one colour per effect in every panel
            hatch = "//" if e.startswith("compensated_") else None  # as in (b)
            c.bar(
                x - 0.4 + (i + 0.5) * w,
                v,
                w,
                color=colour,
                hatch=hatch,
                edgecolor="w" if hatch else None,
                label=_entry_label(e),
            )
        c.set_xticks(x, designs, rotation=20)
        c.set_yscale("symlog", linthresh=1e-3)
        c.set(xlabel=xlabel, ylabel="mean ‖δφ‖ [mrad]", title="(c) orientation error of each entry")
        c.title.set_fontsize(9)
        c.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=3, frameon=False)
    fig.suptitle(
        "Error budget over RW_C: pulley geometry, cable elasticity, winch exit point"
        + (", cable sag" if "sag" in effects else "")
        + " (physical equilibrium)",
        fontsize=10,
    )
    return save(fig, out)


def _effects(t):
    """The single effects of a budget table: the three, and ``sag`` when it has that entry (heavy
    cables, ``analyses.budget.effects_of``)."""
    return (
        ("pulley", "elasticity", "winch", "sag")
        if (t.entry == "sag").any()
        else ("pulley", "elasticity", "winch")
    )


def _entry_label(e):
    """The legend label of a budget entry."""
    if e == "neglected_sag":
        return "sag added (massless compensation)"
    return e.replace("compensated_", "compensating ")


def budget_paths(paths, out):
    """Error budget along the section 3.3.1 paths: ‖δp‖ of each effect alone, all together, the
    interaction and the error left after compensating pulley geometry (with heavy cables also sag
    alone and what sag adds under the massless compensated lengths), versus the arc length s; one
    panel per design, one legend for all under the panels. ``paths`` maps a design label to its
    budget path table (s and one column of ‖δp‖ [m] per budget entry, NaN where a variant is not ok)."""
    labels = list(paths)
    cols = 2 if len(labels) > 1 else 1
    rows = int(np.ceil(len(labels) / cols))
    fig, axes = plt.subplots(
        rows, cols, figsize=(6.5 * cols, 3.8 * rows + 0.8), squeeze=False, layout="constrained"
    )
    for ax, label in zip(axes.ravel(), labels):
        df = paths[label]
        cols = ("pulley", "elasticity", "winch", "sag") if "sag" in df else ("pulley", "elasticity", "winch")
        for e in (*cols, "interaction", "all"):
            ax.plot(df.s, df[e] * 1e3, color=EFFECT_COLOURS[e], lw=1.8 if e == "all" else 1.1, label=e)
        ax.plot(df.s, df["compensated_pulley"] * 1e3, "k:", lw=1, label="after compensating pulleys")
        if "neglected_sag" in df:
            ax.plot(
                df.s, df["neglected_sag"] * 1e3, "--", color=EFFECT_COLOURS["sag"], lw=1, label="sag added"
            )
        ax.set_yscale("log")
        ax.set(xlabel="position along the path s [m]", ylabel="‖δp‖ [mm]", title=label)
        ax.grid(alpha=0.3, which="both")
    handles, names = axes.ravel()[0].get_legend_handles_labels()
    fig.legend(handles, names, loc="outside lower center", ncol=6, fontsize=7)
    for ax in axes.ravel()[len(labels) :]:
        ax.set_axis_off()
    fig.suptitle("Error budget along the section 3.3.1 paths (physical equilibrium)", fontsize=10)
    return save(fig, out)
