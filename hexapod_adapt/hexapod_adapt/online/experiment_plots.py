# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Pictures of the adaptation experiment (thesis figs 5.4-5.5), PNG; ROS-free.

:func:`plot_experiment`: adapted speed per scenario (box plots, the damaged control tripod per
scenario and the intact one as references) and trials per scenario (with the 24-trial = 2-minute
line); one box per trial engine.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Sequence

from hexapod_adapt.online.mboa import TRIAL_BUDGET
from hexapod_util.files import save_png
import matplotlib.pyplot as plt
import numpy as np


def _engine_boxes(ax, rows, quantity, scenarios, engine, k, n_engines, width, colours) -> None:
    """Draw one engine's box per scenario of ``quantity``, the ``k``-th of ``n_engines``."""
    data = [
        [getattr(r, quantity) for r in rows if r.scenario == s and r.trial_engine == engine]
        for s in scenarios
    ]
    positions = np.arange(len(scenarios)) + (k - (n_engines - 1) / 2) * width
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
    label = f'trials on {engine} (map: {rows[0].map_engine})'
    ax.plot([], [], color=colours[k % len(colours)], lw=8, alpha=0.55, label=label)


def _tripod_lines(ax, rows, scenarios, engines, width, colours) -> None:
    """Draw the control tripod's speed, damaged (per scenario) and intact, on each engine."""
    for k, engine in enumerate(engines):
        offset = (k - (len(engines) - 1) / 2) * width
        for i, s in enumerate(scenarios):
            damaged = np.mean(
                [r.control_speed for r in rows if r.scenario == s and r.trial_engine == engine]
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


def plot_experiment(
    rows: Sequence[Any],
    out_speed: str | Path,
    out_trials: str | Path,
    out_ratio: str | Path | None = None,
) -> tuple[Path, ...]:
    """
    Box plots of an adaptation experiment (rows: hexapod_adapt.online.adaptation.ExperimentRow).

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
            _engine_boxes(ax, rows, quantity, scenarios, engine, k, len(engines), width, colours)
        if quantity == 'best_speed':
            _tripod_lines(ax, rows, scenarios, engines, width, colours)
        elif quantity == 'trials':
            ax.axhline(
                TRIAL_BUDGET, color='tab:red', ls='--', label=f'{TRIAL_BUDGET} trials = 2 minutes'
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
    saved = (save_png(figures[0], out_speed), save_png(figures[1], out_trials))
    return saved + ((save_png(figures[2], out_ratio),) if with_ratio else ())
