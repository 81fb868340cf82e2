# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Footfall patterns and diagrams (thesis figs. 2.2-2.4, 3.11).

A footfall pattern is an (N, 6) boolean array, True where a leg is in stance/contact. It comes
from the controller (:func:`hexapod_gait.stance_mask`) or from measured foot contacts
(the simulator); :func:`plot_footfall` draws either the same way.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np


def swing_groups(pattern: np.ndarray) -> list[frozenset[int]]:
    """
    List the distinct sets of legs (1-based) that are off the ground together.

    In order of first appearance; rows where every leg is in stance are skipped.
    """
    seen: list[frozenset[int]] = []
    for row in np.asarray(pattern, dtype=bool):
        group = frozenset(int(i) + 1 for i in np.flatnonzero(~row))
        if group and group not in seen:
            seen.append(group)
    return seen


def plot_footfall(
    pattern: np.ndarray, times: np.ndarray, path: str | Path, title: str = ''
) -> Path:
    """Save a footfall diagram (black = foot on the ground) as PNG; returns the path."""
    # optional: matplotlib is only needed to draw, so the gait library loads without it
    import matplotlib

    matplotlib.use('Agg')
    import matplotlib.pyplot as plt

    pat = np.asarray(pattern, dtype=bool)
    t = np.asarray(times, dtype=float)
    if pat.ndim != 2 or pat.shape[1] != 6 or pat.shape[0] != t.size:
        raise ValueError(f'pattern must be (N, 6) matching {t.size} times, got {pat.shape}')
    dt = float(np.median(np.diff(t))) if t.size > 1 else 1.0
    fig, ax = plt.subplots(figsize=(8, 2.6), dpi=120)
    for leg in range(6):
        on = pat[:, leg].astype(np.int8)
        edges = np.flatnonzero(np.diff(np.concatenate([[0], on, [0]])))
        spans = [(t[a], (t[b - 1] + dt) - t[a]) for a, b in zip(edges[::2], edges[1::2])]
        ax.broken_barh(spans, (5 - leg + 0.15, 0.7), facecolors='black')
    ax.set_yticks([5 - leg + 0.5 for leg in range(6)], [f'leg {leg + 1}' for leg in range(6)])
    ax.set_ylim(0, 6)
    ax.set_xlim(t[0], t[-1] + dt)
    ax.set_xlabel('time [s]')
    if title:
        ax.set_title(title)
    fig.tight_layout()
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out)
    plt.close(fig)
    return out
