"""Figures of what the cables' weight adds (issue 38; ``cdpr.pipeline.sag``): the path with and
without sag, and the cables at a corner pose drawn from the elastic catenary."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from cdpr.pipeline.plots.style import mode_suffix, save

#: One colour per cable (cable i: COLOURS[i % len]).
COLOURS = [
    "tab:blue",
    "tab:orange",
    "tab:green",
    "tab:red",
    "tab:purple",
    "tab:brown",
    "tab:pink",
    "tab:olive",
]


def sag_path(df, name, sag, out, mode=None):
    """||dp|| along the path with and without sag, and the pose error sag adds (their solved
    positions' distance), against the path's abscissa s.

    Parameters
    ----------
    df : pandas.DataFrame
        ``cdpr.pipeline.sag.sag_path``'s table.
    name : str
        The study's name (in the title).
    sag : dict
        The study's ``sag`` section (robot keys in the legend).
    out : str or Path
        The .png written (a .pdf beside it).
    mode : {"paper", "physical", None}
        The study's redundancy mode, named in the title.
    """
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7.5, 6.5), sharex=True, layout="constrained")
    s = df["s"].to_numpy()
    a1.plot(s, df["dp_massless_m"], color="0.3", lw=1.2, label=f"{sag['massless']} (massless cables)")
    a1.plot(s, df["dp_heavy_m"], color="tab:blue", lw=1.4, label=f"{sag['robot']} (heavy cables)")
    a1.set(ylabel="||δp|| [m]")
    a1.legend(fontsize=8)
    a1.grid(alpha=0.3)
    a2.plot(s, df["sag_adds_m"], color="tab:red", lw=1.4, label="|p_s(heavy) − p_s(massless)|")
    if "sag_max_m" in df and np.isfinite(df["sag_max_m"].to_numpy(dtype=float)).any():
        a2.plot(s, df["sag_max_m"], color="tab:blue", ls="--", lw=1.0, label="largest cable sag")
    a2.set(xlabel="s, distance along the path from its start [m]", ylabel="[m]")
    a2.legend(fontsize=8)
    a2.grid(alpha=0.3)
    p0, p1 = df[["x", "y", "z"]].iloc[0].to_numpy(), df[["x", "y", "z"]].iloc[-1].to_numpy()
    fig.suptitle(
        f"{name}: pose error sag adds along ({', '.join(f'{v:g}' for v in p0)}) → "
        f"({', '.join(f'{v:g}' for v in p1)}) m, commanded with L_TS{mode_suffix(mode)}",
        fontsize=9,
    )
    return save(fig, out)


def sag_corner(geom, out, mode=None):
    """The heavy cables at one pose drawn from the catenary (``scans.catenary_geometry``): left,
    each cable in its own vertical plane (horizontal distance from B_i, height) with its chord
    dashed; right, each cable's deflection from its chord against the distance along it.

    Parameters
    ----------
    geom : dict
        ``scans.pose_geometry`` with ``scans.catenary_geometry``'s keys.
    out : str or Path
        The .png written (a .pdf beside it).
    mode : {"paper", "physical", None}
        The study's redundancy mode, named in the title.
    """
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11.0, 5.0), layout="constrained")
    poly, B = geom["catenary"], geom["B"]
    for i in range(len(poly)):
        c = COLOURS[i % len(COLOURS)]
        P = poly[i] - B[i]
        horiz = np.hypot(P[:, 0], P[:, 1])
        a1.plot(
            horiz, poly[i][:, 2], color=c, lw=1.4, label=f"cable {i + 1}: t_B = {geom['catenary_t'][i]:.0f} N"
        )
        a1.plot([horiz[0], horiz[-1]], [poly[i][0, 2], poly[i][-1, 2]], color=c, ls="--", lw=0.8)
        chord = P[-1] / np.linalg.norm(P[-1])
        along = P @ chord
        off = np.linalg.norm(P - along[:, None] * chord, axis=1)
        a2.plot(along, off, color=c, lw=1.4, label=f"cable {i + 1}: sag {geom['catenary_sag'][i]:.3g} m")
    a1.set(
        xlabel="horizontal distance from B_i [m]",
        ylabel="z [m]",
        title="in each cable's vertical plane (chords dashed)",
    )
    a2.set(
        xlabel="distance along the chord B_i → D_i [m]",
        ylabel="deflection from the chord [m]",
        title="deflection from the chord",
    )
    for a in (a1, a2):
        a.title.set_fontsize(9)
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    p = ", ".join(f"{v:g}" for v in geom["p"])
    fig.suptitle(
        f"{geom['name']}: cables at p = ({p}) m drawn from the elastic catenary{mode_suffix(mode)}",
        fontsize=10,
    )
    return save(fig, out)
