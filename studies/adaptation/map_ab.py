# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
r"""
Two maps, one experiment: which adapts better on physics that made neither (a ship decision).

Each map runs the damage-informed prior's experiment (lifted legs, S1-S4, 21 runs, the default
profile, the damaged tripod as the floor, adapt_node's tip guard), its prior read from the map's
own cached lifted-leg ceilings, its trials on ``--trial-engine`` (PyBullet: not the maps'
engine, and not the judge). No ceiling is computed on the trial engine (a full one is hours per
case there): the rows hold the adapted speed, trials and tipped trials.

Decision rule for shipping the map of 2026-12-05 (written before the run): the new map ships if
its mean adapted speed on PyBullet is at least the old map's and its tipped trials are no more.

    python -m studies.adaptation.map_ab --a OLD.npz OLD_CEILINGS --b NEW.npz NEW_CEILINGS
"""

from __future__ import annotations

import argparse
from pathlib import Path
import statistics
import sys

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.simulation import engine_of_map
from hexapod_adapt.online.adaptation import DEFAULT_TIP_GUARD
from hexapod_adapt.online.ceiling import ceiling
from hexapod_adapt.online.experiment import ExperimentRow, ExperimentSetup, run_experiment
from hexapod_adapt.online.mboa import PROFILES


def adapt_with_prior(map_path: Path, ceilings: Path, trial_engine: str) -> list[ExperimentRow]:
    """Run the prior's 21 lifted-leg runs of one map with trials on ``trial_engine``."""
    archive = load_archive(map_path)
    map_engine = engine_of_map(archive)

    def priors(damage):  # the map re-scored under the damage (read from the cache; walked if not)
        return ceiling(archive, damage, map_engine, ceilings, 1).speeds

    setup = ExperimentSetup(
        config=PROFILES['default'],
        trial_engine=trial_engine,
        floor=True,
        priors=priors,
        setup='default+prior',
        tip_guard=DEFAULT_TIP_GUARD,
    )
    return run_experiment(archive, setup, on_row=lambda row: print(line(row), flush=True))


def line(r: ExperimentRow) -> str:
    """Say one run: its adapted speed, trials and tipped trials, and its damaged tripod's."""
    legs = '+'.join(map(str, r.failed_legs))
    return (
        f'{r.scenario} legs {legs}: {r.best_speed:.3f} m/s in {r.trials} trials,'
        f' {r.tipped_trials} tipped (tripod {r.control_speed:.3f})'
    )


def summary(rows: list[ExperimentRow]) -> str:
    """Mean adapted speed, median (mean) trials, tipped trials, runs beating the damaged tripod."""
    return (
        f'mean {statistics.fmean(r.best_speed for r in rows):.3f} m/s,'
        f' median {statistics.median(r.trials for r in rows):g} trials'
        f' (mean {statistics.fmean(r.trials for r in rows):.2f}),'
        f' {sum(r.tipped_trials for r in rows)} tipped,'
        f' {sum(r.best_speed > r.control_speed for r in rows)} / {len(rows)} beat the tripod'
    )


def main(argv: list[str] | None = None) -> int:
    """Run both maps; print each one's summary."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--a', nargs=2, type=Path, metavar=('MAP', 'CEILINGS'), required=True)
    parser.add_argument('--b', nargs=2, type=Path, metavar=('MAP', 'CEILINGS'), required=True)
    parser.add_argument('--trial-engine', default='pybullet', choices=('pybullet', 'mujoco'))
    args = parser.parse_args(argv)
    results = {}
    for name, (map_path, ceilings) in (('a', args.a), ('b', args.b)):
        print(f'== {name}: {map_path}', flush=True)
        results[name] = summary(adapt_with_prior(map_path, ceilings, args.trial_engine))
        print(f'{name}: {results[name]}', flush=True)
    for name, line in results.items():
        print(f'{name} ({getattr(args, name)[0]}): {line}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
