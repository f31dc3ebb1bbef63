"""The parity chart (the study's summary): every paper number against ours with its tolerance band."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from cdpr.pipeline.plots.style import OKABE_ITO, mode_suffix, save


def parity_chart(summary_tab, out, mode=None):
    """Every paper number against ours (``summary.csv`` rows with a paper value), one panel per
    unit, with the line of equality and each number's tolerance band (|ours − paper| ≤ tolerance:
    reproduced, filled marker; else open marker)."""
    t = summary_tab[summary_tab.paper.notna() & summary_tab.ours.notna()].copy()
    t = t[pd_numeric(t.paper) & pd_numeric(t.ours)]
    units = list(dict.fromkeys(t.unit.astype(str)))
    fig, axes = plt.subplots(
        1, max(len(units), 1), figsize=(4.2 * max(len(units), 1), 4.6), squeeze=False, layout="constrained"
    )
    for ax, unit in zip(axes[0], units):
        g = t[t.unit.astype(str) == unit]
        p, o, tol = (g[c].astype(float).to_numpy() for c in ("paper", "ours", "tolerance"))
        ok = np.abs(o - p) <= tol + 1e-12
        ax.errorbar(p, p, yerr=tol, fmt="none", ecolor="0.6", capsize=3, lw=4, alpha=0.5)
        ax.plot(p[ok], o[ok], "o", color=OKABE_ITO[2], ms=5, label=f"within tolerance ({ok.sum()})")
        ax.plot(p[~ok], o[~ok], "o", mfc="none", color=OKABE_ITO[1], ms=5, label=f"outside ({(~ok).sum()})")
        lo, hi = float(min(p.min(), o.min())), float(max(p.max(), o.max()))
        pad = 0.05 * (hi - lo if hi > lo else 1.0)
        ax.plot([lo - pad, hi + pad], [lo - pad, hi + pad], "k:", lw=0.8)
        ax.set(xlabel=f"paper [{unit}]", ylabel=f"ours [{unit}]", title=f"{len(g)} numbers in {unit}")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")
    fig.suptitle(f"Paper numbers against ours (grey bar: tolerance){mode_suffix(mode)}", fontsize=10)
    return save(fig, out)


def pd_numeric(col):
    """Whether each entry of ``col`` reads as a finite number."""

    v = pd.to_numeric(col, errors="coerce")
    return np.isfinite(v.to_numpy(dtype=float))
