"""Figures are deterministic: the same data gives the same PNG and PDF bytes (no embedded date)."""

import time

import matplotlib.pyplot as plt

from cdpr import plots


def test_same_figure_gives_same_bytes(tmp_path):
    blobs = []
    for i in range(2):
        fig, ax = plt.subplots()
        ax.plot([0.0, 1.0, 2.0], [0.0, 1.0, 4.0])
        out = tmp_path / f"f{i}.png"
        paths = plots.save(fig, out)
        assert [p.suffix for p in paths] == [".png", ".pdf"]
        blobs.append([p.read_bytes() for p in paths])
        time.sleep(1.1)  # a creation date in seconds would differ
    assert blobs[0] == blobs[1]
