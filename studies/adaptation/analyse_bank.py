# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Does a damage bank help M-BOA? Replay the default profile with and without one on the tuning map.

The bank (hexapod_adapt.online.bank) is the tuning map under every one- and two-leg lifted failure
(studies/out/bank). Three sets of runs, each replayed from ceilings (hexapod_adapt.online.replay):
- out of set: the 63 tuning cases (locked legs, weak servos, lost tibias: none in the bank);
- in set: the 21 lifted cases themselves (the bank holds the truth);
- left out: the same 21, each with its own case dropped from the bank.
Stopping rules compared: M-BOA's (best >= alpha x the mixture's highest mean), 'expected max'
(alpha x the weighted mean of each hypothesis's highest mean) and 'most likely' (alpha x the
most likely hypothesis's highest mean).

    python -m studies.adaptation.analyse_bank > studies/adaptation/results/analyses.txt
"""

from __future__ import annotations

import argparse
from dataclasses import replace
import sys

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.online.bank import BANK_DAMAGES, load_bank
from hexapod_adapt.online.ceiling import cached_ceiling
from hexapod_adapt.online.mboa import Mboa, PROFILES, StopReason
from hexapod_adapt.online.replay import control_speeds
import numpy as np
from studies.tuning_set import TUNING_DAMAGES, TUNING_MAX_TRIALS

MAP = 'studies/out/tuning_map_s2.npz'


def level(opt: Mboa, rule: str) -> float:
    """Return the speed the stopping rule compares the best trial with (before alpha)."""
    means, w = opt.hypothesis_means, opt.weights
    if rule == 'mboa':
        return float(np.max(opt.mean))
    if rule == 'expected max':
        return float(w @ means.max(axis=1))
    return float(means[int(np.argmax(w))].max())  # most likely


def run(
    archive, ceiling, hypotheses, floor: float, rule: str, known_std: float = 0.0
) -> tuple[float, int]:
    """Return (ratio to the ceiling, trials) of one replayed run."""
    niches = archive.elite_indices()
    config = replace(
        PROFILES['default'],
        max_trials=TUNING_MAX_TRIALS,
        min_speed=min(max(floor, 0.0), 2.0),
        known_std=known_std,
    )
    opt = Mboa(
        archive.descriptors[niches], archive.speeds()[niches], config, hypotheses=hypotheses
    )
    while len(opt.trials) < config.max_trials:
        best = opt.best()
        if (
            best is not None
            and best.measured >= config.min_speed
            and best.measured >= config.alpha * level(opt, rule)
        ) or opt.stop_reason() is StopReason.MAP_EXHAUSTED:
            break
        i = opt.next_index()
        opt.observe(i, float(ceiling.speeds[i]))
    return opt.best().measured / ceiling.best_speed, len(opt.trials)


def main(argv: list[str] | None = None) -> int:
    # no options: --help says what the study does instead of running it
    argparse.ArgumentParser(description=__doc__.strip().splitlines()[0]).parse_args(argv)
    archive = load_archive(MAP)
    bank = load_bank(archive, 'mujoco', ['studies/out/bank'])
    floors = control_speeds(BANK_DAMAGES + TUNING_DAMAGES, 'mujoco', archive.trial_duration)
    sets = {
        'out of set': (TUNING_DAMAGES, 'studies/out/ceilings', lambda d: bank.speeds),
        'in set': (BANK_DAMAGES, 'studies/out/bank', lambda d: bank.speeds),
        'left out': (BANK_DAMAGES, 'studies/out/bank', lambda d: bank.without(d).speeds),
    }
    print('bank            rule           damage      median  10th pct  min    median trials')
    for name, (damages, where, hypotheses) in sets.items():
        for label, rule, use, known_std in (
            ('none', 'mboa', False, 0.0),
            ('21 lifted', 'mboa', True, 0.0),
            ('21 lifted', 'expected max', True, 0.0),
            ('21 lifted', 'most likely', True, 0.0),
            # known models under a tight GP, and an 'unknown damage' hypothesis (2026-11-23)
            *(
                (f'+unknown {k:g}', rule, True, k)
                for k in (0.02, 0.03, 0.05)
                for rule in ('mboa', 'expected max')
            ),
        ):
            out = [
                run(
                    archive,
                    cached_ceiling(archive, d, 'mujoco', [where]),
                    hypotheses(d) if use else None,
                    floors[d],
                    rule,
                    known_std,
                )
                for d in damages
            ]
            ratio = np.array([r for r, _ in out])
            print(
                f'{label:15s} {rule:14s} {name:10s}  {np.median(ratio):.3f}   '
                f'{np.percentile(ratio, 10):.3f}    {ratio.min():.3f}  '
                f'{np.median([t for _, t in out]):.0f}',
                flush=True,
            )
    return 0


if __name__ == '__main__':
    sys.exit(main())
