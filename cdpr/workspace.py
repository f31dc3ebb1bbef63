"""Point sets and workspace measures: cell-centred grids, deterministic shards, error-limited
volumes (section 3.3.3) and regular workspaces (section 4.1.1)."""
from __future__ import annotations

import numpy as np

from .errors import CdprError


def check_box(box):
    """Validate a box (xmin, xmax, ymin, ymax, zmin, zmax) [m]; returns it as a float array."""
    b = np.asarray(box, dtype=float)
    if b.shape != (6,) or not np.isfinite(b).all():
        raise CdprError(f"a box needs six finite numbers XMIN XMAX YMIN YMAX ZMIN ZMAX, got {list(box)}")
    if not (b[0] < b[1] and b[2] < b[3] and b[4] < b[5]):
        raise CdprError(f"a box needs XMIN < XMAX, YMIN < YMAX and ZMIN < ZMAX, got {b.tolist()}")
    return b


def cell_centres(lo, hi, n):
    """n cell centres of [lo, hi]: lo + (i + 1/2)(hi - lo)/n."""
    return lo + (np.arange(n) + 0.5) * (hi - lo) / n


def grid_points(box, n, start=0, stop=None):
    """Points start..stop-1 of the n^3 cell-centred grid of ``box`` in C order (x slowest, z
    fastest), shape (k, 3). Computing a slice never builds the whole grid."""
    b = check_box(box)
    total = n**3
    stop = total if stop is None else min(stop, total)
    idx = np.arange(start, stop)
    i, rem = np.divmod(idx, n * n)
    j, k = np.divmod(rem, n)
    axes = [cell_centres(b[2 * a], b[2 * a + 1], n) for a in range(3)]
    return np.column_stack([axes[0][i], axes[1][j], axes[2][k]])


def shard_range(total, shard, shards):
    """[start, stop) of shard ``shard`` (0-based) out of ``shards`` equal contiguous slices."""
    if not (shards >= 1 and 0 <= shard < shards):
        raise CdprError(f"shard must satisfy 0 <= shard < shards, got shard={shard}, shards={shards}")
    return total * shard // shards, total * (shard + 1) // shards
