# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
M-BOA's settings scored on maps of the deployed kind (CMA-MAE), not on the 2,000-niche map.

The default profile was chosen on ``studies/out/tuning_map_s2.npz`` (iso+line, 2,000 niches), and
it did not carry over to the default map's S4 (studies/adaptation/README.md: the target gaits of a
large CMA-MAE map are rarer). This set is the map study's two seed-2 CMA-MAE maps (10,000 and
20,000 niches, 200,000 evaluations: the default map's method, another seed) under the tuning damage
(locked, weak, lost tibia; never S1-S4's lifted legs) on one orientation of each scenario's leg
set: leg 1 (S1-like), legs 1+4 (S2), 1+3 (S3), 1+2 (S4). 2 maps x 3 kinds x 4 leg sets = 24 cases,
replayed from their ceilings (``studies/out/map_study/ceilings``; the study computed legs 1, 1+2
and 1+3, this adds 1+4) with the product's 24-trial budget and the damaged tripod as each run's
floor, over the grid of ``studies.adaptation.score_grid`` (without a bank).

The rule, fixed before the runs: the setting with the highest **worst leg-set median ratio**
(the lowest, over the four leg sets, of the median adapted/ceiling of their 6 cases), compared
in steps of 0.005; ties go to the higher 10th-percentile ratio, then to fewer median trials.
It replaces the default profile only if its worst leg-set median beats the default's by more
than 0.02.

    python -m studies.adaptation.score_grid_deployed  # its section of results/grids.txt
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
from dataclasses import asdict, replace
import functools
from pathlib import Path
import sys

from hexapod_adapt.mapping.archive import Archive, load_archive
from hexapod_adapt.online.ceiling import Ceiling, ceiling
from hexapod_adapt.online.mboa import MboaConfig, PROFILES
from hexapod_adapt.online.replay import control_speeds, score, TuningRun
from hexapod_sim.damage import Damage
from hexapod_util.files import atomic_write_bytes
import numpy as np
from studies.adaptation.score_grid import grid_configs
from studies.tuning_set import TUNING_KINDS, TUNING_MAX_TRIALS

MAPS = ('studies/out/map_study/cma_mae_10000_s2.npz', 'studies/out/map_study/cma_mae_20000_s2.npz')
CACHE = 'studies/out/map_study/ceilings'
LEG_SETS = {'S1': (1,), 'S2': (1, 4), 'S3': (1, 3), 'S4': (1, 2)}
DAMAGES = tuple(Damage.of(k, legs) for k in TUNING_KINDS for legs in LEG_SETS.values())
MARGIN = 0.02  # a winner must beat the default's worst leg-set median by more than this
OUT = Path('studies/out/grid_deployed.csv')


def leg_set(run: TuningRun, damages: dict[str, tuple[int, ...]]) -> str:
    """Return the scenario name of a run's leg set."""
    legs = damages[run.damage]
    return next(name for name, s in LEG_SETS.items() if s == legs)


def evaluate(
    cases: list[tuple[Archive, list[Ceiling], dict]], config: MboaConfig
) -> dict[str, float]:
    """Replay every case with ``config``; return its figures."""
    ratios: dict[str, list[float]] = {name: [] for name in LEG_SETS}
    every, trials = [], []
    for archive, ceilings, controls in cases:
        legs_of = {c.damage.label: c.damage.failed_legs for c in ceilings}
        for run in score(archive, ceilings, controls, config):
            ratios[leg_set(run, legs_of)].append(run.ratio)
            every.append(run.ratio)
            trials.append(run.trials)
    medians = {name: float(np.median(v)) for name, v in ratios.items()}
    return {
        'worst_leg_set_median': min(medians.values()),
        **{f'median_{name}': m for name, m in medians.items()},
        'ratio_median': float(np.median(every)),
        'ratio_p10': float(np.percentile(every, 10)),
        'ratio_min': float(np.min(every)),
        'trials_median': float(np.median(trials)),
    }


def main(argv: list[str] | None = None) -> int:
    # no options: --help says what the study does instead of running it
    argparse.ArgumentParser(description=__doc__.strip().splitlines()[0]).parse_args(argv)
    """Score the grid on the deployed-kind tuning set; print the rule's choice."""
    cases = []
    for path in MAPS:
        archive = load_archive(path)
        ceilings = [ceiling(archive, d, 'mujoco', CACHE, workers=2) for d in DAMAGES]
        controls = control_speeds(DAMAGES, 'mujoco', archive.trial_duration)
        cases.append((archive, ceilings, controls))
        print(f'{path}: {len(archive.elite_indices())} gaits, {len(ceilings)} cases', flush=True)
    configs = [c for c in grid_configs() if not c.use_bank]
    default = replace(PROFILES['default'], max_trials=TUNING_MAX_TRIALS)
    with cf.ProcessPoolExecutor(2) as pool:
        figures = list(pool.map(functools.partial(evaluate, cases), configs, chunksize=4))
    base = evaluate(cases, default)
    names = ('length_scale', 'signal_variance', 'alpha', 'kappa', 'stop_gain')
    rows = [{**{n: asdict(c)[n] for n in names}, **f} for c, f in zip(configs, figures)]
    rows = [{k: 0.0 if v is None else v for k, v in r.items()} for r in rows]  # CSV: 0 = none
    lines = [','.join(rows[0])] + [','.join(f'{v:.6g}' for v in r.values()) for r in rows]
    atomic_write_bytes(OUT, ('\n'.join(lines) + '\n').encode())

    def show(label: str, row: dict) -> None:
        print(label + ' ' + ' '.join(f'{k}={v:.4g}' for k, v in row.items()), flush=True)

    show('default:', {n: asdict(default)[n] for n in names} | base)
    rows.sort(
        key=lambda r: (
            -round(r['worst_leg_set_median'] / 0.005),
            -r['ratio_p10'],
            r['trials_median'],
        )
    )
    for r in rows[:10]:
        show('        ', r)
    best = rows[0]
    gain = best['worst_leg_set_median'] - base['worst_leg_set_median']
    verdict = 'replaces the default' if gain > MARGIN else 'the default stays'
    print(
        f'the rule: best worst leg-set median {best["worst_leg_set_median"]:.3f} against the'
        f" default's {base['worst_leg_set_median']:.3f} ({gain:+.3f}, margin {MARGIN}):"
        f' {verdict}'
    )
    return 0


if __name__ == '__main__':
    sys.exit(main())
