# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Choosing M-BOA's settings honestly: on a tuning set that is not the reported experiment.

The tuning set (issue 19): a map made with another seed (``studies/adaptation/make_tuning_map.sh``)
and damage other than S1-S4's lifted legs (:data:`TUNING_DAMAGES`: locked legs, weak servos, lost
tibias). Every gait of the map is evaluated once per damage case (a ceiling,
:mod:`hexapod_adapt.online.ceiling`). A simulated trial is deterministic, so a run over the map is
replayed from its ceiling: a trial of a gait is its ceiling speed (:func:`lookup_trial`). That
makes a setting's score over 63 damage cases cost a second, and lets every candidate setting be
scored on identical trials.

    python -m studies.adaptation.score_grid \
        --archive studies/out/tuning_map_s2.npz --cache-dir studies/out/ceilings
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
from dataclasses import asdict
import functools
import itertools
from pathlib import Path
import sys
from typing import Sequence

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.simulation import engine_of_map
from hexapod_adapt.online.bank import load_bank
from hexapod_adapt.online.ceiling import ceiling
from hexapod_adapt.online.mboa import MboaConfig
from hexapod_adapt.online.replay import (
    control_speeds,
    residual_statistics,
    score,
    summarise,
    Summary,
)
from hexapod_util.cli import input_file, number, output_dir, output_file, run_command
from hexapod_util.files import atomic_write_bytes
from studies.tuning_set import TUNING_DAMAGES, TUNING_MAX_TRIALS

#: The candidate settings scored on the tuning set: the thesis's values and the levers the
#: evidence points at (length scale, signal variance, stop ratio, exploration, expected-gain stop).
GRID = {
    'length_scale': (0.05, 0.1, 0.15, 0.2, 0.3, 0.4),
    'signal_variance': (1.0, 0.01),
    'alpha': (0.8, 0.9, 0.95, 1.0),
    'kappa': (0.05, 0.5),
    'stop_gain': (None, 0.002, 0.005),  # None: no expected-gain stop
    'use_bank': (False, True),
}


def grid_configs(grid: dict[str, Sequence[float]] = GRID) -> list[MboaConfig]:
    """
    Every combination of ``grid``'s values, as configurations.

    An expected-gain stop needs the signal variance in physical units: with unit variance the
    posterior's spread (~1 m/s) never lets the expected gain fall below a few mm/s, so those
    combinations are left out.
    """
    names = list(grid)
    configs = []
    for values in itertools.product(*(grid[n] for n in names)):
        config = MboaConfig(max_trials=TUNING_MAX_TRIALS, **dict(zip(names, values)))
        if config.stop_gain is not None and config.signal_variance >= 1.0:
            continue
        configs.append(config)
    return configs


def _score_one(archive, ceilings, controls, bank, config: MboaConfig) -> Summary:
    return summarise(score(archive, ceilings, controls, config, bank))


def build_parser() -> argparse.ArgumentParser:
    """Return the command-line options of ``python -m studies.adaptation.score_grid``."""
    ap = argparse.ArgumentParser(
        prog='score_grid', description="Score M-BOA settings on the tuning set's cached ceilings."
    )
    ap.add_argument('--archive', type=input_file, required=True, help='the tuning map')
    ap.add_argument('--cache-dir', type=output_dir, required=True, help='cached ceilings')
    ap.add_argument(
        '--bank-dir',
        type=output_dir,
        default=None,
        help="the tuning map's damage bank (hexapod_adapt.online.bank: its lifted-leg ceilings);"
        ' without it, settings that use a bank are scored without one',
    )
    ap.add_argument(
        '--workers', type=number(int, 1, 256), default=2, help='processes (ceilings, scoring)'
    )
    ap.add_argument('--out', type=output_file, default=None, help='CSV of every setting scored')
    return ap


def main(argv: list[str] | None = None) -> int:
    """Score the grid; print the settings that meet the targets, best first."""
    args = build_parser().parse_args(argv)

    def run() -> int:
        archive = load_archive(args.archive)
        engine = engine_of_map(archive)
        ceilings = [
            ceiling(archive, d, engine, args.cache_dir, args.workers) for d in TUNING_DAMAGES
        ]
        controls = control_speeds(TUNING_DAMAGES, engine, archive.trial_duration)
        bank = load_bank(archive, engine, [args.bank_dir]) if args.bank_dir else None
        if bank is not None:
            print(f'damage bank: {bank.describe()}', flush=True)
            if set(bank.damages) & set(TUNING_DAMAGES):
                raise ValueError('the bank holds a tuning case: it would be tuned on its answer')
        stats = residual_statistics(archive, ceilings)
        print(
            f'damaged - map speed over {len(ceilings)} cases: mean {stats["mean"]:.3f} m/s,'
            f" variance {stats['total']:.4f} (m/s)^2, about each case's mean"
            f' {stats["within"]:.4f} (m/s)^2',
            flush=True,
        )
        configs = grid_configs()
        with cf.ProcessPoolExecutor(args.workers) as pool:
            summaries = list(
                pool.map(
                    functools.partial(_score_one, archive, ceilings, controls, bank),
                    configs,
                    chunksize=4,
                )
            )
        rows = [
            {**{k: getattr(c, k) for k in GRID}, **asdict(s)} for c, s in zip(configs, summaries)
        ]
        if args.out:
            lines = [','.join(rows[0])] + [
                ','.join(f'{v:.6g}' if isinstance(v, float) else str(v) for v in r.values())
                for r in rows
            ]
            atomic_write_bytes(Path(args.out), ('\n'.join(lines) + '\n').encode())
        keep = [r for r in rows if r['trials_max'] <= 24 and r['walking_median'] <= 30.0]
        keep.sort(key=lambda r: (-r['ratio_median_worst_group'], -r['ratio_min']))
        print(f'{len(keep)} of {len(rows)} settings within 24 trials and 30 s median walking')
        for r in keep[:15]:
            print(
                ' '.join(
                    f'{k}={v:.4g}' if isinstance(v, float) else f'{k}={v}' for k, v in r.items()
                )
            )
        return 0

    return run_command('score_grid', run, 'cached ceilings are kept; run again to go on')


if __name__ == '__main__':
    sys.exit(main())
