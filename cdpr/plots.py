"""One function per figure family. Each reads a table (DataFrame) and writes PNG and PDF."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .io import atomic  # noqa: E402


def save(fig, out):
    """Write ``out`` (.png) and its .pdf sibling atomically; returns both paths. The PDF carries no
    creation date, so the same table gives the same bytes."""
    out = Path(out)
    paths = [out, out.with_suffix(".pdf")]
    meta = {".png": None, ".pdf": {"CreationDate": None}}
    for p in paths:
        atomic(p, lambda tmp, p=p: fig.savefig(tmp, format=p.suffix[1:], dpi=150, bbox_inches="tight", metadata=meta[p.suffix]))
    plt.close(fig)
    return paths


def _grid(df, value):
    xs, ys = np.sort(df.x.unique()), np.sort(df.y.unique())
    Z = np.full((len(ys), len(xs)), np.nan)
    ix, iy = np.searchsorted(xs, df.x), np.searchsorted(ys, df.y)
    Z[iy, ix] = value
    return xs, ys, Z


def plane_contours(df, title, out):
    """Fig. 12: iso-contours of |dp| [m] over a horizontal plane; non-ok points left blank."""
    ok = (df.status == "ok").to_numpy()
    xs, ys, Z = _grid(df, np.where(ok, df.dp, np.nan))
    fig, ax = plt.subplots(figsize=(5, 4.4))
    cf = ax.contourf(xs, ys, Z, levels=14, cmap="viridis")
    cs = ax.contour(xs, ys, Z, levels=7, colors="k", linewidths=0.5)
    ax.clabel(cs, fmt="%.3f", fontsize=7)
    fig.colorbar(cf, ax=ax, label="|dp| [m]")
    ax.set(xlabel="x [m]", ylabel="y [m]", title=title, aspect="equal")
    return save(fig, out)


def subset_map(df, title, out):
    """Fig. 9: the 3-cable subset that minimises |dp| at each point of the plane."""
    labels = sorted(s for s in df.subset.unique() if s)
    code = df.subset.map({s: i for i, s in enumerate(labels)}).astype(float)
    code[df.status != "ok"] = np.nan
    xs, ys, Z = _grid(df, code.to_numpy())
    fig, ax = plt.subplots(figsize=(5, 4.4))
    cmap = plt.get_cmap("tab10", max(len(labels), 1))
    im = ax.pcolormesh(xs, ys, Z, cmap=cmap, vmin=-0.5, vmax=len(labels) - 0.5, shading="nearest")
    cb = fig.colorbar(im, ax=ax, ticks=range(len(labels)))
    cb.ax.set_yticklabels([f"cables {s}" for s in labels])
    ax.set(xlabel="x [m]", ylabel="y [m]", title=title, aspect="equal")
    return save(fig, out)


def curves(series, xlabel, ylabel, title, out, markers=None):
    """Generic line plot: ``series`` is a list of (x, y, label)."""
    fig, ax = plt.subplots(figsize=(6, 4))
    for x, y, label in series:
        ax.plot(x, y, label=label)
    for x, y, label in markers or []:
        ax.plot(x, y, "o", label=label)
    ax.set(xlabel=xlabel, ylabel=ylabel, title=title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return save(fig, out)


def bars(labels, values, ylabel, title, out, groups=None):
    """Bar chart; ``groups`` optionally a list of (name, values) to draw side by side."""
    fig, ax = plt.subplots(figsize=(6.5, 4))
    if groups is None:
        groups = [(None, values)]
    w = 0.8 / len(groups)
    x = np.arange(len(labels))
    for k, (name, vals) in enumerate(groups):
        ax.bar(x + (k - (len(groups) - 1) / 2) * w, vals, w, label=name)
    ax.set_xticks(x, labels, rotation=30, ha="right")
    ax.set(ylabel=ylabel, title=title)
    ax.grid(axis="y", alpha=0.3)
    if groups[0][0] is not None:
        ax.legend(fontsize=8)
    return save(fig, out)
