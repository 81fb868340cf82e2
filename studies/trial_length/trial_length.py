# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
r"""
How long a trial should be (thesis 7.0.1): adapted speed against walking time, per trial length.

A robot trial starts from standing: the gait first settles (``settle`` s, one default gait
period, not timed), then the speed is timed over the trial length. Shorter trials cost less
walking but measure each gait less well, so M-BOA may choose worse gaits. For each trial length
this runs M-BOA on every damage case of a set with such settled trials in simulation; the adapted
gait is then judged by its speed in the map's own 5 s measure under the damage (the ceiling's
figure), so every trial length is judged alike.

    python -m studies.trial_length.trial_length --archive studies/out/tuning_map_s2.npz \\
        --cache-dir studies/out/ceilings --out studies/trial_length/results/trial_length.csv
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass, replace
from pathlib import Path
import sys
from typing import Any, Callable, Sequence

from hexapod_adapt.mapping.archive import Archive, load_archive
from hexapod_adapt.mapping.simulation import engine_of_map
from hexapod_adapt.online.adaptation import map_speed, simulated_trial
from hexapod_adapt.online.ceiling import approximate_ceiling, Ceiling, ceiling
from hexapod_adapt.online.mboa import MboaConfig, PROFILES, TRIAL_BUDGET
from hexapod_adapt.online.session import adapt
from hexapod_sim import create_simulator, ENGINES, SimConfig
from hexapod_util.cli import input_file, output_dir, output_file, run_command
from hexapod_util.files import atomic_write_bytes, save_png
import matplotlib.pyplot as plt
import numpy as np
from studies.tuning_set import TUNING_DAMAGES

TRIAL_LENGTHS = (1.0, 2.0, 3.0, 5.0)
#: Untimed walking before a trial is timed [s]: one period of the controller's default 1 s cycle.
SETTLE_S = 1.0


@dataclass(frozen=True)
class LengthRun:
    """One run with one trial length on one damage case."""

    trial_length: float  # s
    engine: str
    damage: str
    trials: int
    adapted_speed: float  # the chosen gait in the map's 5 s measure under the damage [m/s]
    ceiling_speed: float  # m/s
    ratio: float
    walking_time: float  # s, settling included


def run_lengths(
    archive: Archive,
    ceilings: Sequence[Ceiling],
    config: MboaConfig,
    engine: str,
    lengths: Sequence[float] = TRIAL_LENGTHS,
    settle: float = SETTLE_S,
    on_run: Callable[[LengthRun], None] | None = None,
) -> list[LengthRun]:
    """Adapt on every case with each trial length; trials on ``engine``."""
    runs = []
    with create_simulator(SimConfig(engine=engine)) as sim:
        for length in lengths:
            for c in ceilings:
                trial = simulated_trial(archive, c.damage, sim, length, settle)
                result = adapt(archive, trial, config)
                known = dict(zip(c.niches.tolist(), c.speeds.tolist()))
                speed = known.get(result.best_niche)
                if speed is None:  # outside an approximate ceiling's gaits: measure it alike
                    speed = map_speed(archive, result.best_niche, c.damage, sim)
                run = LengthRun(
                    length,
                    engine,
                    c.damage.label,
                    len(result.trials),
                    speed,
                    c.best_speed,
                    speed / c.best_speed,
                    len(result.trials) * (settle + length),
                )
                runs.append(run)
                if on_run:
                    on_run(run)
    return runs


def plot_trial_length(runs: Sequence[Any], out: str | Path) -> Path:
    """
    Adapted/ceiling ratio and walking time against the trial length (thesis 7.0.1).

    ``runs``: :class:`studies.trial_length.trial_length.LengthRun` rows, one line per engine.
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
    return save_png(fig, out)


def build_parser() -> argparse.ArgumentParser:
    """Return the command-line options of ``python -m studies.trial_length.trial_length``."""
    ap = argparse.ArgumentParser(prog='trial_length', description=__doc__.split('\n\n')[0])
    ap.add_argument('--archive', type=input_file, required=True, help='map')
    ap.add_argument('--cache-dir', type=output_dir, required=True, help='cached ceilings')
    ap.add_argument(
        '--engine', choices=ENGINES, nargs='+', default=None, help="trial engines (the map's)"
    )
    ap.add_argument(
        '--profile', choices=sorted(PROFILES), default='default', help='M-BOA settings'
    )
    ap.add_argument('--every', type=int, default=1, help='use every n-th damage case of the set')
    ap.add_argument(
        '--top',
        type=int,
        default=100,
        help="on an engine other than the map's, the ceiling is approximated by this many gaits,"
        " those that walk best under the damage on the map's engine",
    )
    ap.add_argument('--out', type=output_file, default=None, help='CSV of every run')
    ap.add_argument('--plot', type=output_file, default=None, help='PNG of the curve')
    return ap


def main(argv: list[str] | None = None) -> int:
    """Run every trial length on the tuning set; print the median ratio and walking time."""
    args = build_parser().parse_args(argv)

    def run() -> int:
        archive = load_archive(args.archive)
        map_engine = engine_of_map(archive)
        damages = TUNING_DAMAGES[:: max(1, args.every)]
        config = replace(PROFILES[args.profile], max_trials=TRIAL_BUDGET)
        runs = []
        for engine in args.engine or [map_engine]:
            # the ratio is against the trial engine's own ceiling (cached, or computed)
            ceilings = [
                ceiling(archive, d, engine, args.cache_dir)
                if engine == map_engine
                else approximate_ceiling(
                    archive,
                    d,
                    engine,
                    ceiling(archive, d, map_engine, args.cache_dir),
                    args.top,
                    args.cache_dir,
                )
                for d in damages
            ]
            runs += run_lengths(archive, ceilings, config, engine)
            for length in TRIAL_LENGTHS:
                sel = [r for r in runs if r.trial_length == length and r.engine == engine]
                print(
                    f'BENCH trial_length_{length:g}s_{engine}_ratio_median'
                    f' {np.median([r.ratio for r in sel]):.3f} 1\n'
                    f'BENCH trial_length_{length:g}s_{engine}_walking_median'
                    f' {np.median([r.walking_time for r in sel]):.1f} s',
                    flush=True,
                )
        if args.out:
            head = (
                'trial_length,engine,damage,trials,adapted_speed,ceiling_speed,ratio,walking_time'
            )
            lines = [head] + [
                f'{r.trial_length:g},{r.engine},"{r.damage}",{r.trials},{r.adapted_speed:.6f},'
                f'{r.ceiling_speed:.6f},{r.ratio:.6f},{r.walking_time:g}'
                for r in runs
            ]
            atomic_write_bytes(args.out, ('\n'.join(lines) + '\n').encode())
        if args.plot:
            print(f'wrote {plot_trial_length(runs, args.plot)}')
        return 0

    return run_command('trial_length', run, 'nothing is written until every run is done')


if __name__ == '__main__':
    sys.exit(main())
