# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Have the engines converged in their time step on a map's gaits? (issue 49, deliverable 2).

Each engine's step was chosen on the control tripod (a slow, wide walk). A map's fastest gaits
load the servos harder, so this walks them at a ladder of finer steps and says how far each
figure moves: each engine's physics steps per 240 Hz row (the row's target held through
them). Gaits: a map's
``--fastest`` fastest and ``--random`` others (seed 0), intact, 5 s from standing, collisions not
fatal, measured as ``engine_disagreement`` measures them. Printed per engine and level: medians
of speed and tracking, and against the finest level the median |speed difference| and the
Spearman of the gaits' speeds.

    python -m studies.engines.step_refinement [--archive MAP] [--fastest 8] [--random 8] \
        [--engines mujoco pybullet dart] [--out studies/out/step_refinement.csv]
"""

from __future__ import annotations

import argparse
import csv
from dataclasses import asdict, dataclass, replace
import os
import time

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
from hexapod_adapt.mapping.transfer import ranked_gaits
from hexapod_sim import create_simulator, SimConfig
from hexapod_sim.engine_settings import ACCURATE, DART_DEFAULT_SETTINGS, DEFAULT_SETTINGS
import numpy as np
from scipy.stats import spearmanr
from studies.engines.engine_disagreement import StepStats, walk


@dataclass(frozen=True)
class Level:
    """One rung of an engine's ladder: its name and the configuration that runs it."""

    engine: str
    name: str  # e.g. '240 Hz', '4 substeps'
    config: SimConfig


def ladder(engine: str) -> list[Level]:
    """The engine's levels, coarsest first; the shipped default is among them."""
    if engine == 'mujoco':
        return [
            Level(
                engine,
                f'{n} substeps',
                SimConfig(engine, mujoco=replace(DEFAULT_SETTINGS, substeps=n)),
            )
            for n in (1, 2, 4, 8)
        ]
    if engine == 'pybullet':
        return [
            Level(
                engine, f'{n} substeps', SimConfig(engine, pybullet=replace(ACCURATE, substeps=n))
            )
            for n in (4, 8, 16, 32)
        ]
    return [
        Level(
            engine,
            f'{n} substeps',
            SimConfig(engine, dart=replace(DART_DEFAULT_SETTINGS, substeps=n)),
        )
        for n in (2, 4, 8, 16, 32)
    ]


def agreement(rows: list[tuple[str, StepStats]], engines: list[str]) -> None:
    """Print each pair of engines' Spearman at their finest levels and at their defaults."""
    defaults = {'mujoco': DEFAULT_SETTINGS, 'pybullet': ACCURATE, 'dart': DART_DEFAULT_SETTINGS}

    def speeds(engine: str, level: str) -> np.ndarray:
        return np.array([r.speed for name, r in rows if r.engine == engine and name == level])

    print('| engines | Spearman, each at its default | each at its finest |')
    print('|---|---|---|')
    for i, a in enumerate(engines):
        for b in engines[i + 1 :]:
            at = {e: (f'{defaults[e].substeps} substeps', ladder(e)[-1].name) for e in (a, b)}
            cells = [spearmanr(speeds(a, at[a][k]), speeds(b, at[b][k])).statistic for k in (0, 1)]
            print(f'| {a} vs {b} | {cells[0]:.2f} | {cells[1]:.2f} |')


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--archive', default=None, help='a map (default: the shipped default map)')
    parser.add_argument('--fastest', type=int, default=8)
    parser.add_argument('--random', type=int, default=8)
    parser.add_argument('--engines', nargs='+', default=['mujoco', 'pybullet', 'dart'])
    parser.add_argument('--out', default=None, help='CSV: every gait at every level')
    args = parser.parse_args()
    archive = load_archive(args.archive or str(shipped_map(DEFAULT_MAP)))
    niches = ranked_gaits(archive, args.fastest, args.random, seed=0)
    speeds = archive.speeds()
    rows: list[tuple[str, StepStats]] = []
    for engine in args.engines:
        levels = ladder(engine)
        by_level: dict[str, list[StepStats]] = {}
        for level in levels:
            t0 = time.monotonic()
            with create_simulator(level.config) as sim:
                got = [walk(sim, archive.genotypes[n], int(n), float(speeds[n])) for n in niches]
            by_level[level.name] = got
            rows += [(level.name, r) for r in got]
            print(
                f'{engine} {level.name}: {len(niches)} gaits in {time.monotonic() - t0:.0f} s',
                flush=True,
            )
        finest = np.array([r.speed for r in by_level[levels[-1].name]])
        print(
            f'\n| {engine} | speed | track coxa / femur / tibia | feet down | saturated '
            f'| median abs speed change vs finest | Spearman vs finest |'
        )
        print('|---|---|---|---|---|---|---|')
        for level in levels:
            got = by_level[level.name]
            speed = np.array([r.speed for r in got])
            med = {
                f: float(np.median([getattr(r, f) for r in got]))
                for f in StepStats.__dataclass_fields__
                if f not in ('engine',)
            }
            rho = spearmanr(speed, finest).statistic if level is not levels[-1] else 1.0
            print(
                f'| {level.name} | {med["speed"]:.3f} | {med["track_coxa"]:.3f} / '
                f'{med["track_femur"]:.3f} / {med["track_tibia"]:.3f} | {med["feet_down"]:.2f} '
                f'| {med["saturated"]:.3f} | {float(np.median(np.abs(speed - finest))):.3f} '
                f'| {rho:.2f} |',
                flush=True,
            )
        print()
    agreement(rows, args.engines)
    if args.out:
        tmp = f'{args.out}.tmp'
        with open(tmp, 'w', newline='') as f:
            writer = csv.DictWriter(f, fieldnames=['level', *StepStats.__dataclass_fields__])
            writer.writeheader()
            writer.writerows({'level': name, **asdict(r)} for name, r in rows)
        os.replace(tmp, args.out)


if __name__ == '__main__':
    main()
