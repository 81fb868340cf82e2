# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Pictures of maps (PNG, matplotlib's headless Agg backend); ROS-free.

* :func:`plot_progress` -- a map generation's QD progress from its JSON-lines log (thesis figs
  4.7-4.8): filled niches, max / mean / median / 5th-percentile fitness and QD-score against
  evaluations. Works on the log of a run still in progress.
* :func:`plot_projections` -- the 6-D map as 2-D projections: for every pair of legs, the best
  speed over a grid of their two duty factors.
* :func:`plot_repertoire`, :func:`plot_repertoire_progress` -- a step map (navigation
  repertoire): where its steps end, and its generation.

The experiments' pictures are beside them: :mod:`hexapod_adapt.online.experiment_plots`,
:mod:`hexapod_navigation.offline.plots`.
"""

from __future__ import annotations

from dataclasses import dataclass
import itertools
import json
from pathlib import Path
from typing import Any, Sequence

from hexapod_adapt.mapping.archive import Archive
from hexapod_util.files import save_png
import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402 - after choosing the headless backend
from matplotlib.ticker import EngFormatter, MaxNLocator  # noqa: E402
import numpy as np  # noqa: E402


def _log_rows(path: str | Path) -> list[dict[str, Any]]:
    """Return the rows of a map-generation log in the order they were written."""
    rows = []
    for line in Path(path).read_text().splitlines():
        try:
            row = json.loads(line)
        except (json.JSONDecodeError, RecursionError):
            continue
        if isinstance(row, dict) and 'evaluations' in row:
            rows.append(row)
    return rows


def read_log(path: str | Path) -> list[dict[str, Any]]:
    """
    Return the rows of a map-generation log (JSON lines).

    A torn last line (run in progress) is skipped.

    Rows from several resumed runs are kept in order of their evaluation counts.
    """
    return sorted(_log_rows(path), key=lambda r: r['evaluations'])


@dataclass(frozen=True)
class LogRun:
    """One run of a map-generation log: from a start or a resume to where its log ends."""

    evaluations: int  # the count at its last row
    elapsed: float  # s of wall time
    workers: int
    cpu_s: float | None  # CPU seconds it used (None: a log written before rows had it)

    @property
    def core_seconds(self) -> float:
        """Return the cores the run held: its wall time x its worker processes."""
        return self.elapsed * self.workers


def log_runs(path: str | Path, default_workers: int = 2) -> list[LogRun]:
    """
    Return the runs of a map-generation log, in the order they ran.

    A resumed run restarts ``elapsed``, and its rows may repeat the evaluation counts of the
    previous run's last rows (the work after the checkpoint it resumed from), so runs are told
    apart in the order the rows were written, never sorted. ``default_workers``: for rows written
    before they had ``workers``.
    """
    runs: list[LogRun] = []
    previous = None
    rows = _log_rows(path)
    for row in rows + [None]:
        if previous is not None and (row is None or row['elapsed'] < previous['elapsed']):
            runs.append(
                LogRun(
                    int(previous['evaluations']),
                    float(previous['elapsed']),
                    int(previous.get('workers', default_workers)),
                    float(previous['cpu_s']) if 'cpu_s' in previous else None,
                )
            )
        previous = row
    return runs


def evaluation_axes(axes: Any) -> None:
    """Label every axis's x as evaluations, in engineering notation, with a light grid."""
    for ax in axes:
        ax.set_xlabel('evaluations')
        ax.xaxis.set_major_locator(MaxNLocator(5))
        ax.xaxis.set_major_formatter(EngFormatter(sep=''))  # 200k, 1M: long counts overlap
        ax.grid(alpha=0.3)


def plot_progress(
    rows: Sequence[dict[str, Any]], out: str | Path, trial_duration: float = 5.0, title: str = ''
) -> Path:
    """QD progress of a map generation (fitness shown as speed, m/s)."""
    if not rows:
        raise ValueError('the log has no progress rows yet')
    ev = np.array([r['evaluations'] for r in rows], dtype=float)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    axes[0].plot(ev, [r['filled'] for r in rows], color='tab:blue')
    axes[0].set_ylabel('filled niches')
    for key, label, style in (
        ('max', 'max', '-'),
        ('mean', 'mean', '--'),
        ('median', 'median', '-.'),
        ('p5', '5th percentile', ':'),
    ):
        axes[1].plot(
            ev, np.array([r[key] for r in rows], dtype=float) / trial_duration, style, label=label
        )
    axes[1].set_ylabel('elite speed (m/s)')
    axes[1].legend(loc='lower right', fontsize=8)
    axes[2].plot(ev, [r['qd_score'] for r in rows], color='tab:green')
    axes[2].set_ylabel('QD-score (sum of elite fitness, m)')
    evaluation_axes(axes)
    fig.suptitle(title or 'map generation progress')
    return save_png(fig, out)


def plot_projections(archive: Archive, out: str | Path, bins: int = 20, title: str = '') -> Path:
    """Best speed over each pair of legs' duty factors (15 panels, one colour scale)."""
    speeds = archive.speeds()
    filled = archive.filled
    if not filled.any():
        raise ValueError('the archive has no gaits to draw')
    d, v = archive.descriptors[filled], speeds[filled]
    pairs = list(itertools.combinations(range(6), 2))
    fig, axes = plt.subplots(3, 5, figsize=(16, 9.5))
    vmin, vmax = float(np.nanmin(v)), float(np.nanmax(v))
    image = None
    for ax, (i, j) in zip(axes.flat, pairs):
        grid = np.full((bins, bins), np.nan)
        xi = np.minimum((d[:, i] * bins).astype(int), bins - 1)
        yj = np.minimum((d[:, j] * bins).astype(int), bins - 1)
        for x, y, s in zip(xi, yj, v):
            if not s <= grid[y, x]:  # NaN or lower: keep the best
                grid[y, x] = s
        image = ax.imshow(
            grid,
            origin='lower',
            extent=(0, 1, 0, 1),
            vmin=vmin,
            vmax=vmax,
            cmap='viridis',
            aspect='equal',
        )
        ax.set_xlabel(f'duty factor leg {i + 1}', fontsize=8)
        ax.set_ylabel(f'leg {j + 1}', fontsize=8)
        ax.tick_params(labelsize=7)
    fig.subplots_adjust(wspace=0.45, hspace=0.35)
    fig.colorbar(image, ax=axes, shrink=0.8, label='best speed (m/s)')
    fig.suptitle(
        title
        or f'{archive.n_filled} gaits in {archive.n_niches} niches: best speed per pair of legs'
    )
    return save_png(fig, out)


def plot_repertoire(archive: Archive, out: str | Path, title: str = '') -> Path:
    """Draw where each step of a navigation repertoire ends, coloured by its heading change."""
    from hexapod_adapt.mapping.steps import from_descriptor

    if not archive.filled.any():
        raise ValueError('the repertoire has no gaits to draw')
    idx = archive.elite_indices()
    xy = from_descriptor(archive.descriptors[idx])
    fig, ax = plt.subplots(figsize=(6.2, 5.4))
    image = ax.scatter(
        xy[:, 0], xy[:, 1], c=np.degrees(-archive.fitness[idx]), s=9, cmap='magma_r', vmin=0
    )
    fig.colorbar(image, ax=ax, label='heading change over the step [deg]')
    ax.plot(0, 0, 'k+', ms=10)
    ax.set_aspect('equal')
    ax.set_xlabel('x after one step [m] (start frame)')
    ax.set_ylabel('y [m]')
    ax.grid(alpha=0.3)
    ax.set_title(
        title
        or f'{len(idx)} gaits of {archive.n_niches} niches, {archive.trial_duration:g} s steps'
    )
    return save_png(fig, out)


def plot_repertoire_progress(
    rows: Sequence[dict[str, Any]], out: str | Path, title: str = ''
) -> Path:
    """Draw a navigation repertoire's generation: filled niches and the elites' heading changes."""
    if not rows:
        raise ValueError('the log has no progress rows yet')
    ev = np.array([r['evaluations'] for r in rows], dtype=float)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    axes[0].plot(ev, [r['filled'] for r in rows], color='tab:blue')
    axes[0].set_ylabel('filled niches (places one step reaches)')
    for key, label, style in (
        ('mean', 'mean', '--'),
        ('median', 'median', '-.'),
        ('p5', 'worst 5 %', ':'),
    ):
        axes[1].plot(
            ev, -np.degrees(np.array([r[key] for r in rows], dtype=float)), style, label=label
        )
    axes[1].set_ylabel('heading change of the elites [deg]')
    axes[1].legend(loc='upper right', fontsize=8)
    evaluation_axes(axes)
    fig.suptitle(title or 'navigation repertoire generation progress')
    return save_png(fig, out)
