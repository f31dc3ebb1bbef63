"""The figures of the calibration (issue 18; ``cdpr calibrate fit --report`` and the calibration
studies of ``cdpr.pipeline.calibration``): residuals, estimates
and posterior correlation of a fit, the learning curve of the CDPR4 study and the validation errors
of the 6-DoF study.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from cdpr.pipeline.plots.style import save

#: The figures of ``calibration_figures``.
FIT_FIGURES = ("residuals", "estimates", "correlation")


def calibration_figures(result, folder, names=None):
    """Three figures of a ``calibration.fit`` result in ``folder``: residuals.png, estimates.png,
    correlation.png (a PDF beside each).

    Parameters
    ----------
    result : Calibration
    folder : Path
    names : dict, optional
        Figure (``FIT_FIGURES``) -> its path relative to ``folder``; the calibration studies pass
        their results layout's (``cdpr.pipeline.results.CALIBRATION_OUTPUTS``). Default
        ``<figure>.png``.
    """
    names = names or {k: f"{k}.png" for k in FIT_FIGURES}
    folder = Path(folder)
    t = result.table
    fig, ax = plt.subplots(figsize=(7, 3.5))
    x = np.arange(len(t))
    ax.semilogy(x, t["residual_before_m"] * 1e3, "o", ms=3, label="nominal robot")
    ax.semilogy(x, t["residual_after_m"] * 1e3, "s", ms=3, label=f"calibrated ({result.model} model)")
    ax.set_xlabel("sample")
    ax.set_ylabel("|measured - predicted| [mm]")
    ax.legend()
    ax.set_title("Pose residual per sample")
    save(fig, folder / names["residuals"])

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
    save(fig, folder / names["estimates"])

    fig, ax = plt.subplots(figsize=(6, 5))
    im = ax.imshow(result.correlation, vmin=-1, vmax=1, cmap="RdBu_r")
    n = len(result.names)
    ax.set_xticks(range(n), result.names, rotation=90, fontsize=6)
    ax.set_yticks(range(n), result.names, fontsize=6)
    fig.colorbar(im, ax=ax, label="posterior correlation")
    ax.set_title("Posterior correlation")
    save(fig, folder / names["correlation"])


def learning_curve(curve, floor_mm, path, label="pulleys + elasticity"):
    """The validation RMS of each design versus the number of calibration samples (log-log), with
    the truth robot's noise floor.

    Parameters
    ----------
    curve : DataFrame
        Columns design, n, predict_rms_mm [mm].
    floor_mm : float
        The noise floor [mm] (the truth robot's validation RMS).
    path : str or Path
        The .png written (a .pdf beside it, ``save``).
    label : str
        The model named in the title.
    """
    fig, ax = plt.subplots(figsize=(5.5, 3.5))
    for design, g in curve.dropna(subset=["predict_rms_mm"]).groupby("design"):
        ax.loglog(g["n"], g["predict_rms_mm"], "o-", label=design)
    ax.axhline(floor_mm, color="k", ls=":", label="truth robot (noise floor)")
    ax.set_xlabel("calibration samples")
    ax.set_ylabel("validation RMS [mm]")
    ax.legend()
    ax.set_title(f"Learning curve, {label} model")
    save(fig, path)


def validation_errors(vt, models, pretensioned, path, name, command):
    """Sorted prediction errors (position and orientation) of every model on the validation poses
    (solid), and of the models of ``pretensioned`` on the pretensioned validation (dashed, in the
    colour of the model's solid line).

    Parameters
    ----------
    vt : DataFrame
        The validation table: columns ``<key>_position_mm`` [mm] and ``<key>_orientation_mrad``
        [mrad] per model.
    models : dict
        Model label -> its column prefix ``key`` in ``vt``, in the order drawn.
    pretensioned : dict
        Model label (a label of ``models``) -> (position [m], orientation [rad]) errors on the
        pretensioned validation, in the order drawn.
    path : str or Path
        The .png written (a .pdf beside it, ``save``).
    name : str
        The robot's name (in the title).
    command : str
        The study's commands (in the title).
    """
    fig, axes = plt.subplots(1, 2, figsize=(9, 4.4), layout="constrained")
    colours = {}
    for label, key in models.items():
        for ax, col in zip(axes, ("position_mm", "orientation_mrad")):
            e = np.sort(vt[f"{key}_{col}"].dropna().to_numpy())
            (line,) = ax.semilogx(e, np.arange(1, len(e) + 1) / len(e), label=label)
            colours[label] = line.get_color()
    for label, errors in pretensioned.items():
        for ax, err in zip(axes, errors):
            e = np.sort(1e3 * err[np.isfinite(err)])
            ax.semilogx(
                e,
                np.arange(1, len(e) + 1) / len(e),
                "--",
                color=colours[label],
                label=f"{label}, pretensioned",
            )
    axes[0].set_xlabel("|predicted - measured| position [mm]")
    axes[1].set_xlabel("|predicted - measured| orientation [mrad]")
    for ax in axes:
        ax.set_ylabel("fraction of validation poses [-]")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=4, fontsize=7)  # off the curves
    fig.suptitle(f"{name}: validation errors per model (physical mode, {command} commands)")
    save(fig, path)
