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
Choosing M-BOA's settings honestly: on a tuning set that is not the reported experiment.

The tuning set (issue 19): a map made with another seed (``tuning/make_tuning_map.sh``) and damage
other than S1-S4's lifted legs (:data:`TUNING_DAMAGES`: locked legs, weak servos, lost tibias).
Every gait of the map is evaluated once per damage case (a ceiling, :mod:`hexapod_adapt.ceiling`).
A simulated trial is deterministic, so a run over the map is replayed from its ceiling: a trial
of a gait is its ceiling speed (:func:`lookup_trial`). That makes a setting's score over 63 damage
cases cost a second, and lets every candidate setting be scored on identical trials.

    python -m hexapod_adapt.tuning --archive tuning/tuning_map_s2.npz --cache-dir tuning/ceilings
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
from dataclasses import asdict, dataclass
import functools
import itertools
from pathlib import Path
import sys
from typing import Callable, Iterable, Sequence

from hexapod_adapt.adaptation import adapt, AdaptationResult
from hexapod_adapt.archive import Archive, atomic_write_bytes, load_archive
from hexapod_adapt.bank import DamageBank, load_bank
from hexapod_adapt.ceiling import Ceiling, ceiling
from hexapod_adapt.mboa import MboaConfig
from hexapod_adapt.simulation import archive_engine
from hexapod_description.cli import input_file, number, output_dir, output_file, run_command
from hexapod_gait import preset
from hexapod_sim import create_simulator, evaluate_gait, SimConfig
from hexapod_sim.damage import Damage
from hexapod_sim.scenarios import scenario
import numpy as np

TUNING_KINDS = ('locked', 'weak', 'no_tibia')
#: Every tuning kind on each single leg and each pair of legs (the S2-S4 pairs): 3 x 21 cases.
TUNING_DAMAGES: tuple[Damage, ...] = tuple(
    Damage.of(kind, legs)
    for kind in TUNING_KINDS
    for name in ('S1', 'S2', 'S3', 'S4')
    for legs in scenario(name)
)
#: Trial budget of a tuning run: the product's, 24 trials (2 minutes of 5 s trials).
TUNING_MAX_TRIALS = 24


def lookup_trial(c: Ceiling) -> Callable[[int], float]:
    """Return a trial function that answers a gait's speed under ``c``'s damage from ``c``."""
    speed = dict(zip(c.niches.tolist(), c.speeds.tolist()))
    return lambda niche: speed[int(niche)]


@dataclass(frozen=True)
class TuningRun:
    """One replayed adaptation run on one damage case."""

    damage: str
    kind: str
    legs: int  # number of damaged legs
    trials: int
    success: bool
    best_speed: float  # m/s
    ceiling_speed: float  # m/s
    ratio: float  # best / ceiling
    control_speed: float  # the damaged control tripod [m/s] (the floor)
    walking_time: float  # s


def replay(
    archive: Archive,
    c: Ceiling,
    config: MboaConfig,
    control_speed: float = 0.0,
    bank: DamageBank | None = None,
) -> AdaptationResult:
    """
    Run M-BOA on ``archive`` with trials answered from ``c`` (floor: ``control_speed``).

    With ``bank`` and ``config.use_bank``, the bank's hypotheses too.
    """
    hypotheses = bank.hypotheses(config.use_bank) if bank is not None else None
    return adapt(
        archive, lookup_trial(c), config, floor=lambda: control_speed, hypotheses=hypotheses
    )


def control_speeds(damages: Iterable[Damage], engine: str, duration: float) -> dict[Damage, float]:
    """Return the control tripod's speed under each damage on ``engine`` [m/s]."""
    with create_simulator(SimConfig(engine=engine)) as sim:
        return {
            d: evaluate_gait(
                preset('control'), sim, duration=duration, collisions_fatal=False, failed_legs=d
            ).speed
            for d in damages
        }


def score(
    archive: Archive,
    ceilings: Sequence[Ceiling],
    controls: dict[Damage, float],
    config: MboaConfig,
    bank: DamageBank | None = None,
) -> list[TuningRun]:
    """Replay one run per damage case with ``config`` (and ``bank``, if it uses one)."""
    runs = []
    for c in ceilings:
        result = replay(archive, c, config, controls[c.damage], bank)
        runs.append(
            TuningRun(
                c.damage.label,
                c.damage.legs[0].kind if c.damage.legs else 'intact',
                len(c.damage.legs),
                len(result.trials),
                result.success,
                result.best_speed,
                c.best_speed,
                result.best_speed / c.best_speed,
                controls[c.damage],
                len(result.trials) * archive.trial_duration,
            )
        )
    return runs


@dataclass(frozen=True)
class Summary:
    """A setting's figures over the tuning set (the issue's acceptance figures)."""

    runs: int
    ratio_median: float
    ratio_min: float
    ratio_p10: float  # 10th percentile
    ratio_median_worst_group: float  # lowest median over (kind, number of legs) groups
    trials_median: float
    trials_max: int
    walking_median: float  # s
    below_control: int  # runs whose best is slower than the damaged control tripod


def summarise(runs: Sequence[TuningRun]) -> Summary:
    """Return the figures of ``runs``."""
    ratio = np.array([r.ratio for r in runs])
    trials = np.array([r.trials for r in runs])
    groups: dict[tuple[str, int], list[float]] = {}
    for r in runs:
        groups.setdefault((r.kind, r.legs), []).append(r.ratio)
    return Summary(
        len(runs),
        float(np.median(ratio)),
        float(np.min(ratio)),
        float(np.percentile(ratio, 10)),
        min(float(np.median(v)) for v in groups.values()),
        float(np.median(trials)),
        int(np.max(trials)),
        float(np.median([r.walking_time for r in runs])),
        sum(r.best_speed < r.control_speed for r in runs),
    )


def residual_statistics(archive: Archive, ceilings: Sequence[Ceiling]) -> dict[str, float]:
    """
    How far damage moves speeds from the map's prediction, over the tuning set [(m/s)^2].

    ``total``: variance of (damaged - map) speed over every gait and case; ``within``: its
    variance about each case's own mean (what a GP around the map's prior has to learn).
    """
    prior = archive.speeds()
    total, within = [], []
    for c in ceilings:
        r = c.speeds - prior[c.niches]
        total.append(r)
        within.append(r - r.mean())
    return {
        'total': float(np.var(np.concatenate(total))),
        'within': float(np.var(np.concatenate(within))),
        'mean': float(np.mean(np.concatenate(total))),
    }


#: The candidate settings scored on the tuning set: the thesis's values and the levers the
#: evidence points at (length scale, signal variance, stop ratio, exploration, expected-gain stop).
GRID = {
    'length_scale': (0.05, 0.1, 0.15, 0.2, 0.3, 0.4),
    'signal_variance': (1.0, 0.01),
    'alpha': (0.8, 0.9, 0.95, 1.0),
    'kappa': (0.05, 0.5),
    'stop_gain': (0.0, 0.002, 0.005),
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
        if config.stop_gain > 0 and config.signal_variance >= 1.0:
            continue
        configs.append(config)
    return configs


def _score_one(archive, ceilings, controls, bank, config: MboaConfig) -> Summary:
    return summarise(score(archive, ceilings, controls, config, bank))


def build_parser() -> argparse.ArgumentParser:
    """Return the command-line options of ``python -m hexapod_adapt.tuning``."""
    ap = argparse.ArgumentParser(
        prog='tuning', description="Score M-BOA settings on the tuning set's cached ceilings."
    )
    ap.add_argument('--archive', type=input_file, required=True, help='the tuning map')
    ap.add_argument('--cache-dir', type=output_dir, required=True, help='cached ceilings')
    ap.add_argument(
        '--bank-dir',
        type=output_dir,
        default=None,
        help="the tuning map's damage bank (hexapod_adapt.bank: its lifted-leg ceilings); without"
        ' it, settings that use a bank are scored without one',
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
        engine = archive_engine(archive.metadata) or 'mujoco'
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

    return run_command('tuning', run, 'cached ceilings are kept; run again to go on')


if __name__ == '__main__':
    sys.exit(main())
