# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Pictures of the navigation experiment: the paths walked, times per method (PNG, no ROS)."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Sequence

from hexapod_util.files import save_png
import matplotlib.pyplot as plt
import numpy as np

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
    return save_png(fig, out)


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
    return save_png(fig, out)
