# Copyright 2026 Hexapod adaptation team
# All rights reserved.
#
# Permission is hereby granted, free of charge, to any person obtaining a copy
# of this software and associated documentation files (the "Software"), to deal
# in the Software without restriction, including without limitation the rights
# to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
# copies of the Software, and to permit persons to whom the Software is
# furnished to do so, subject to the following conditions:
#
# The above copyright notice and this permission notice shall be included in all
# copies or substantial portions of the Software.
#
# THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
# IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
# FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
# AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
# LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
# OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
# SOFTWARE.
"""
Pictures of maps and experiments (PNG, matplotlib's headless Agg backend); ROS-free.

* :func:`plot_progress` -- a map generation's QD progress from its JSON-lines log (thesis figs
  4.7-4.8): filled niches, max / mean / median / 5th-percentile fitness and QD-score against
  evaluations. Works on the log of a run still in progress.
* :func:`plot_projections` -- the 6-D map as 2-D projections: for every pair of legs, the best
  speed over a grid of their two duty factors.
* :func:`plot_experiment` -- thesis figs 5.4-5.5: adapted speed per scenario (box plots, the
  damaged control tripod per scenario and the intact one as references) and trials per scenario
  (with the 24-trial = 2-minute line); one box per trial engine.
"""

from __future__ import annotations

import itertools
import json
from pathlib import Path
from typing import Any, Sequence

from hexapod_adapt.archive import Archive, atomic_output
import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402 - after choosing the headless backend
from matplotlib.ticker import EngFormatter, MaxNLocator  # noqa: E402
import numpy as np  # noqa: E402

TWO_MINUTES_OF_TRIALS = 24  # 24 trials of 5 s = 2 minutes of walking (thesis 5.3.2)


def read_log(path: str | Path) -> list[dict[str, Any]]:
    """
    Return the rows of a map-generation log (JSON lines).

    A torn last line (run in progress) is skipped.

    Rows from several resumed runs are kept in order of their evaluation counts.
    """
    rows = []
    for line in Path(path).read_text().splitlines():
        try:
            row = json.loads(line)
        except json.JSONDecodeError:
            continue
        if isinstance(row, dict) and 'evaluations' in row:
            rows.append(row)
    rows.sort(key=lambda r: r['evaluations'])
    return rows


def _save(fig: Any, out: str | Path) -> Path:
    out = Path(out)
    with atomic_output(out) as fh:
        fig.savefig(fh, format='png', dpi=110, bbox_inches='tight')
    plt.close(fig)
    return out


def _evaluation_axes(axes: Any) -> None:
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
    _evaluation_axes(axes)
    fig.suptitle(title or 'map generation progress')
    return _save(fig, out)


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
    return _save(fig, out)


def plot_experiment(
    rows: Sequence[Any],
    out_speed: str | Path,
    out_trials: str | Path,
    out_ratio: str | Path | None = None,
) -> tuple[Path, ...]:
    """
    Box plots of an adaptation experiment (rows: hexapod_adapt.adaptation.ExperimentRow).

    Adapted speed and trials; with ``out_ratio`` and rows that carry ceilings, adapted/ceiling
    too.
    """
    if not rows:
        raise ValueError('no experiment rows to draw')
    scenarios = sorted({r.scenario for r in rows})
    engines = list(dict.fromkeys(r.trial_engine for r in rows))
    width = 0.8 / len(engines)
    colours = ['tab:blue', 'tab:orange', 'tab:green']
    figures = []
    quantities = [('best_speed', 'adapted speed (m/s)'), ('trials', 'trials')]
    with_ratio = out_ratio is not None and all(r.ceiling_niche >= 0 for r in rows)
    if with_ratio:
        quantities.append(('ratio', "adapted / the map's best gait with the damage"))
    for quantity, ylabel in quantities:
        fig, ax = plt.subplots(figsize=(2.2 + 1.6 * len(scenarios), 5.2))
        for k, engine in enumerate(engines):
            data = [
                [
                    getattr(r, quantity)
                    for r in rows
                    if r.scenario == s and r.trial_engine == engine
                ]
                for s in scenarios
            ]
            positions = np.arange(len(scenarios)) + (k - (len(engines) - 1) / 2) * width
            box = ax.boxplot(
                data,
                positions=positions,
                widths=width * 0.85,
                patch_artist=True,
                manage_ticks=False,
                showmeans=True,  # the thesis's figures mark the mean too
                meanprops={'marker': '^', 'markerfacecolor': 'tab:green', 'markeredgecolor': 'k'},
            )
            for patch in box['boxes']:
                patch.set_facecolor(colours[k % len(colours)])
                patch.set_alpha(0.55)
            ax.plot(
                [],
                [],
                color=colours[k % len(colours)],
                lw=8,
                alpha=0.55,
                label=f'trials on {engine} (map: {rows[0].map_engine})',
            )
        if quantity == 'best_speed':
            for k, engine in enumerate(engines):
                offset = (k - (len(engines) - 1) / 2) * width
                for i, s in enumerate(scenarios):
                    damaged = np.mean(
                        [
                            r.control_speed
                            for r in rows
                            if r.scenario == s and r.trial_engine == engine
                        ]
                    )
                    ax.hlines(
                        damaged,
                        i + offset - width / 2,
                        i + offset + width / 2,
                        colors='tab:red',
                        linestyles='--',
                        label='control tripod, damaged (same engine)' if i == k == 0 else None,
                    )
                intact = next(r.intact_control_speed for r in rows if r.trial_engine == engine)
                ax.axhline(
                    intact,
                    color=colours[k % len(colours)],
                    ls=':',
                    lw=1.2,
                    label=f'control tripod, intact ({engine})',
                )
        elif quantity == 'trials':
            ax.axhline(
                TWO_MINUTES_OF_TRIALS, color='tab:red', ls='--', label='24 trials = 2 minutes'
            )
        else:
            ax.axhline(1.0, color='k', ls=':', lw=1.0, label='the ceiling')
            ax.axhline(0.9, color='tab:red', ls='--', lw=1.0, label='0.9 of the ceiling')
        ax.set_xticks(range(len(scenarios)), scenarios)
        ax.set_xlabel('failure scenario')
        ax.set_ylabel(ylabel)
        ax.grid(axis='y', alpha=0.3)
        # below the axes: inside, it hides reference lines at either end of the range
        ax.legend(fontsize=7, loc='upper center', bbox_to_anchor=(0.5, -0.14), ncol=2)
        fig.tight_layout()
        figures.append(fig)
    saved = (_save(figures[0], out_speed), _save(figures[1], out_trials))
    return saved + ((_save(figures[2], out_ratio),) if with_ratio else ())


# -- the navigation experiment (issue 18) -------------------------------------------------------
NAVIGATION_COLOURS = {'repertoire': 'tab:green', 'no_learning': 'tab:blue', 'tripod': 'tab:red'}


def plot_navigation_paths(rows: Sequence[Any], paths: Sequence[Any], out: str | Path) -> Path:
    """
    Top views of every episode, one panel per (scenario, method): paths, goals, start.

    ``rows`` are navigation_experiment.NavigationRow, ``paths`` their (x, y) lists.
    """
    scenarios = list(dict.fromkeys(r.scenario for r in rows))
    methods = list(dict.fromkeys(r.method for r in rows))
    fig, axes = plt.subplots(
        len(scenarios),
        len(methods),
        figsize=(3.2 * len(methods), 3.2 * len(scenarios)),
        squeeze=False,
        sharex=True,
        sharey=True,
    )
    for i, name in enumerate(scenarios):
        for j, method in enumerate(methods):
            ax = axes[i][j]
            sel = [
                (r, p) for r, p in zip(rows, paths) if r.scenario == name and r.method == method
            ]
            for r, p in sel:
                xy = np.asarray(p, dtype=float).reshape(-1, 2)
                ax.plot(
                    xy[:, 0],
                    xy[:, 1],
                    lw=0.6,
                    alpha=0.6,
                    color=NAVIGATION_COLOURS.get(method, 'k') if r.reached else 'tab:gray',
                )
            goals = {(r.goal_x, r.goal_y) for r, _ in sel}
            ax.scatter(*zip(*goals), marker='x', color='k', s=25, zorder=3)
            ax.plot(0, 0, 'ko', ms=3)
            ok = sum(r.reached for r, _ in sel)
            ax.set_title(f'{name} {method}: {ok}/{len(sel)} reached', fontsize=8)
            ax.set_aspect('equal')
            ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel('x [m]')
    for row in axes:
        row[0].set_ylabel('y [m]')
    return _save(fig, out)


def plot_navigation_boxes(rows: Sequence[Any], out: str | Path) -> Path:
    """
    Draw box plots per scenario and method.

    Walking time and path efficiency of the reached goals, and the success rate.
    """
    scenarios = list(dict.fromkeys(r.scenario for r in rows))
    methods = list(dict.fromkeys(r.method for r in rows))
    fig, axes = plt.subplots(1, 3, figsize=(15, 4))
    width = 0.8 / len(methods)
    for j, method in enumerate(methods):
        pos = np.arange(len(scenarios)) + (j - (len(methods) - 1) / 2) * width
        for ax, field_name in ((axes[0], 'walking_time'), (axes[1], 'efficiency')):
            data = [
                [
                    getattr(r, field_name)
                    for r in rows
                    if r.scenario == s and r.method == method and r.reached
                ]
                or [np.nan]
                for s in scenarios
            ]
            bp = ax.boxplot(
                data, positions=pos, widths=width * 0.9, patch_artist=True, showfliers=True
            )
            for patch in bp['boxes']:
                patch.set_facecolor(NAVIGATION_COLOURS.get(method, 'w'))
                patch.set_alpha(0.6)
        rate = [
            np.mean([r.reached for r in rows if r.scenario == s and r.method == method]) * 100
            for s in scenarios
        ]
        axes[2].bar(
            pos,
            rate,
            width * 0.9,
            color=NAVIGATION_COLOURS.get(method, 'k'),
            alpha=0.7,
            label=method,
        )
    for ax, label in zip(
        axes, ('walking time to the goal [s]', 'path efficiency', 'goals reached [%]')
    ):
        ax.set_xticks(np.arange(len(scenarios)))
        ax.set_xticklabels(scenarios)
        ax.set_ylabel(label)
        ax.grid(axis='y', alpha=0.3)
    axes[2].axhline(85, color='k', lw=0.8, ls='--')
    axes[2].legend(fontsize=8)
    return _save(fig, out)


def plot_repertoire(archive: Archive, out: str | Path, title: str = '') -> Path:
    """Draw where each step of a navigation repertoire ends, coloured by its heading change."""
    from hexapod_adapt.repertoire import from_descriptor

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
    return _save(fig, out)


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
    _evaluation_axes(axes)
    fig.suptitle(title or 'navigation repertoire generation progress')
    return _save(fig, out)


def plot_trial_length(runs: Sequence[Any], out: str | Path) -> Path:
    """
    Adapted/ceiling ratio and walking time against the trial length (thesis 7.0.1).

    ``runs``: :class:`hexapod_adapt.trial_length.LengthRun` rows, one line per engine.
    """
    fig, (left, right) = plt.subplots(1, 2, figsize=(9, 3.6))
    for engine in dict.fromkeys(r.engine for r in runs):
        sel = [r for r in runs if r.engine == engine]
        lengths = sorted({r.trial_length for r in sel})
        ratio = [[r.ratio for r in sel if r.trial_length == t] for t in lengths]
        walking = [[r.walking_time for r in sel if r.trial_length == t] for t in lengths]
        for axes, values in ((left, ratio), (right, walking)):
            med = [float(np.median(v)) for v in values]
            low = [float(np.percentile(v, 25)) for v in values]
            high = [float(np.percentile(v, 75)) for v in values]
            axes.plot(lengths, med, marker='o', label=f'{engine} (median)')
            axes.fill_between(lengths, low, high, alpha=0.2)
    left.set_xlabel('trial length [s] (after 1 s of untimed settling)')
    left.set_ylabel('adapted / ceiling speed')
    left.legend(fontsize=8)
    right.set_xlabel('trial length [s]')
    right.set_ylabel('walking time to adapt [s]')
    right.axhline(30.0, color='red', linestyle='--', linewidth=1, label='30 s')
    right.legend(fontsize=8)
    for axes in (left, right):
        axes.grid(alpha=0.3)
    fig.suptitle('Trial length: what M-BOA finds, and the walking it costs (25-75 % band)')
    fig.tight_layout()
    return _save(fig, out)
