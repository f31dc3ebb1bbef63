"""Calibration figures and the calibration study (issue 18): a seeded true CDPR4, synthetic tracker
data, calibrations with models of increasing fidelity, and their errors on a validation set.

Figures (``calibration_figures``): residuals before/after per sample, estimates with their 95 %
intervals against the prior, the posterior correlation matrix.
"""

from __future__ import annotations

import numpy as np

from cdpr.pipeline.plots import plt, save


def calibration_figures(result, folder):
    """Three figures of a ``calibration.fit`` result in ``folder``: residuals.png, estimates.png,
    correlation.png.

    Parameters
    ----------
    result : Calibration
    folder : Path
    """
    t = result.table
    fig, ax = plt.subplots(figsize=(7, 3.5))
    x = np.arange(len(t))
    ax.semilogy(x, t["residual_before_m"] * 1e3, "o", ms=3, label="nominal robot")
    ax.semilogy(x, t["residual_after_m"] * 1e3, "s", ms=3, label=f"calibrated ({result.model} model)")
    ax.set_xlabel("sample")
    ax.set_ylabel("|measured - predicted| [mm]")
    ax.legend()
    ax.set_title("Pose residual per sample")
    save(fig, folder / "residuals.png")

    pt = result.parameter_table()
    fig, ax = plt.subplots(figsize=(7, max(2.5, 0.22 * len(pt) + 1)))
    y = np.arange(len(pt))
    z = (pt["estimate"] - pt["nominal"]) / pt["prior_sd"]
    ax.errorbar(
        z, y, xerr=1.959964 * pt["sd"] / pt["prior_sd"], fmt="o", ms=3, capsize=2, label="estimate, 95 %"
    )
    ax.axvspan(-1.959964, 1.959964, color="0.9", label="prior 95 %")
    ax.set_yticks(y, pt["name"], fontsize=7)
    ax.set_xlabel("(estimate - nominal) / prior sd")
    ax.invert_yaxis()
    ax.legend(fontsize=7)
    ax.set_title("Estimates against the prior")
    save(fig, folder / "estimates.png")

    fig, ax = plt.subplots(figsize=(6, 5))
    im = ax.imshow(result.correlation, vmin=-1, vmax=1, cmap="RdBu_r")
    n = len(result.names)
    ax.set_xticks(range(n), result.names, rotation=90, fontsize=6)
    ax.set_yticks(range(n), result.names, fontsize=6)
    fig.colorbar(im, ax=ax, label="posterior correlation")
    ax.set_title("Posterior correlation")
    save(fig, folder / "correlation.png")
