"""The figures of the Hangprinter study (``cdpr.pipeline.hangprinter``): the held-out position errors
per model, the anchors with their posterior 95 % ellipses (projected), and the held-out line
residuals against the measured line force.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Ellipse

from cdpr.pipeline.plots.style import OKABE_ITO, save


def _colours(models):
    return {name: OKABE_ITO[i % len(OKABE_ITO)] for i, name in enumerate(models)}


def heldout_errors(cv, samples, st, out):
    """Held-out position error of every sample with a measured position, per model (dots, at the
    study's last fold count) with the RMS at each fold count (bars), one panel per data set; a data
    set without a measured position shows its held-out line RMS instead.

    Parameters
    ----------
    cv : DataFrame
        The study's cv.csv.
    samples : DataFrame
        Its per_sample.csv.
    st : dict
        ``load_hangprinter_study``.
    out : Path
        The .png (a .pdf beside it).

    Returns
    -------
    list of Path
    """
    sets = list(st["data_sets"])
    fig, axes = plt.subplots(
        1, len(sets), figsize=(5.5 * len(sets), 4.6), layout="constrained", squeeze=False
    )
    for ax, ds in zip(axes[0], sets):
        models = st["data_sets"][ds]["models"]
        d = cv[cv.data_set == ds]
        ks = list(dict.fromkeys(d.folds))
        width = 0.8 / len(ks)
        # a session without a measured position: its held-out line residuals instead
        lines = bool(d.heldout_position_rms_mm.isna().all())
        col, scol = (
            ("heldout_line_rms_mm", "line_rms_mm") if lines else ("heldout_position_rms_mm", "error_mm")
        )
        for j, K in enumerate(ks):
            rms = [d[(d.model == m) & (d.folds == K)][col].iloc[0] for m in models]
            x = np.arange(len(models)) - 0.4 + width * (j + 0.5)
            ax.bar(
                x,
                rms,
                width=width,
                color=f"{0.55 + 0.3 * j / max(1, len(ks) - 1):.2f}",
                label=f"RMS, K = {K}",
            )
        s = samples[(samples.data_set == ds) & (samples.folds == ks[-1])]
        rng = np.random.default_rng(0)  # a fixed jitter: the same figure every run
        for i, m in enumerate(models):
            e = s[s.model == m][scol].dropna().to_numpy()
            ax.plot(i + rng.uniform(-0.25, 0.25, len(e)), e, "o", ms=3, color="k", alpha=0.7)
        ax.plot([], [], "o", ms=3, color="k", label=f"each sample, K = {ks[-1]}")
        ax.set_xticks(np.arange(len(models)), models, rotation=30, ha="right", fontsize=8)
        ax.set_ylabel("held-out line RMS [mm]" if lines else "held-out position error [mm]")
        ax.set_title(ds + (" (no measured position: line residuals)" if lines else ""), fontsize=9)
        ax.grid(axis="y", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("Hangprinter: held-out error per model (cross-validation, identical folds)", fontsize=10)
    return save(fig, out)


def anchor_ellipses(ellipses, nominal, st, scale, out):
    """Each anchor's estimate per model as its offset from the nominal robot file [mm], seen from
    above (x, y) and from the side (x, z), with the projected posterior 95 % ellipse of the fitted
    models (the tool's solution and the nominal file: points without one). Rows: data set ×
    projection; columns: anchors.

    Parameters
    ----------
    ellipses : list of dict
        data_set, model, A (m, 3) [m], cov (m, 3, 3) [m^2] or None.
    nominal : dict data set -> ndarray (m, 3) [m]
        The nominal anchors of each data set's robot.
    st : dict
        ``load_hangprinter_study``.
    scale : float
        Ellipse half-axes in posterior sd (``CHI2_95_2D``: 95 % of a 2-D Gaussian).
    out : Path

    Returns
    -------
    list of Path
    """
    sets, models = list(st["data_sets"]), list(st["models"])
    colours = _colours(models)
    m = len(next(iter(nominal.values())))
    proj = (("x", "y", (0, 1)), ("x", "z", (0, 2)))
    fig, axes = plt.subplots(
        2 * len(sets), m, figsize=(3.0 * m, 2.7 * 2 * len(sets)), layout="constrained", squeeze=False
    )
    for r, ds in enumerate(sets):
        for p, (a, b, (ia, ib)) in enumerate(proj):
            for i in range(m):
                ax = axes[2 * r + p, i]
                for e in ellipses:
                    if e["data_set"] != ds:
                        continue
                    off = 1e3 * (e["A"][i] - nominal[ds][i])
                    c = colours[e["model"]]
                    ax.plot(off[ia], off[ib], "o" if e["cov"] is not None else "x", color=c, ms=4)
                    if e["cov"] is not None:
                        C = 1e6 * e["cov"][i][np.ix_([ia, ib], [ia, ib])]
                        w, v = np.linalg.eigh(C)
                        ang = np.degrees(np.arctan2(v[1, 1], v[0, 1]))
                        ax.add_patch(
                            Ellipse(
                                (off[ia], off[ib]),
                                2 * scale * np.sqrt(max(w[1], 0.0)),
                                2 * scale * np.sqrt(max(w[0], 0.0)),
                                angle=ang,
                                fill=False,
                                color=c,
                                lw=1,
                            )
                        )
                ax.axhline(0, color="0.8", lw=0.6)
                ax.axvline(0, color="0.8", lw=0.6)
                ax.set_aspect("equal", adjustable="datalim")
                ax.tick_params(labelsize=7)
                ax.set_xlabel(f"Δ{a} [mm]", fontsize=7)
                ax.set_ylabel(f"Δ{b} [mm]", fontsize=7)
                ax.set_title(f"{ds}: anchor {'ABCDEFGH'[i] if i < 8 else i + 1}, {a}-{b}", fontsize=7)
    marker = {n: "x" if st["models"][n]["fixed"] else "o" for n in models}
    handles = [plt.Line2D([], [], color=colours[n], marker=marker[n], ls="", ms=4) for n in models]
    fig.legend(handles, models, loc="outside lower center", ncol=len(models), fontsize=7, frameon=False)
    fig.suptitle(
        "Hangprinter anchors: offset from the nominal robot file, posterior 95 % ellipses (projected); "
        "x: scored as given",
        fontsize=9,
    )
    return save(fig, out)


def residuals_against_force(samples, st, out):
    """Each held-out line residual (at the sample's solved position, the study's last fold count)
    against the line force the motor driver reported, per fitted model of each data set with
    forces; a panel says so where no data set has forces.

    Parameters
    ----------
    samples : DataFrame
        The study's per_sample.csv.
    st : dict
        ``load_hangprinter_study``.
    out : Path

    Returns
    -------
    list of Path
    """
    fcols = sorted(c for c in samples.columns if c.startswith("force_N_"))
    sets = [ds for ds in st["data_sets"] if samples[samples.data_set == ds][fcols].notna().any().any()]
    models = [
        n
        for n, m in st["models"].items()
        if m["fixed"] is None and any(n in st["data_sets"][ds]["models"] for ds in sets)
    ]
    if not sets:
        fig, ax = plt.subplots(figsize=(5, 2), layout="constrained")
        ax.text(0.5, 0.5, "no data set has line forces", ha="center", va="center")
        ax.set_axis_off()
        return save(fig, out)
    fig, axes = plt.subplots(
        len(sets),
        len(models),
        figsize=(3.2 * len(models), 3.0 * len(sets)),
        layout="constrained",
        squeeze=False,
    )
    m = len(fcols)
    for r, ds in enumerate(sets):
        d = samples[samples.data_set == ds]
        d = d[d.folds == d.folds.max()]
        for c, name in enumerate(models):
            ax = axes[r, c]
            s = d[d.model == name]
            if not len(s):
                ax.set_axis_off()
                continue
            for i in range(m):
                ax.plot(
                    s[f"force_N_{i + 1}"],
                    s[f"line_residual_mm_{i + 1}"],
                    "o",
                    ms=3,
                    color=OKABE_ITO[i % len(OKABE_ITO)],
                    label=f"line {'ABCDEFGH'[i] if i < 8 else i + 1}",
                )
            ax.axhline(0, color="0.6", lw=0.6)
            ax.set_xlabel("line force [N]", fontsize=8)
            ax.set_ylabel("held-out line residual [mm]", fontsize=8)
            ax.set_title(f"{ds}: {name} ({st['models'][name]['model']})", fontsize=7)
            ax.tick_params(labelsize=7)
            ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=6)
    fig.suptitle("Hangprinter: held-out line residuals against the reported line force", fontsize=9)
    return save(fig, out)
