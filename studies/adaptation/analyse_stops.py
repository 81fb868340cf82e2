# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Why M-BOA stops early: replay the thesis profile on the tuning set and look at the GP at the stop.

For every tuning damage case: the ratio reached, the GP's highest posterior mean when the stopping
rule fired, the GP's mean and std at the map's true best gait under that damage, and where that
gait ranked in the prior. Prints one line per case and the medians.

    python -m studies.adaptation.analyse_stops \
        --archive studies/out/tuning_map_s2.npz --cache-dir studies/out/ceilings
"""

from __future__ import annotations

import argparse
from dataclasses import replace
import sys

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.online.adaptation import candidates
from hexapod_adapt.online.ceiling import ceiling
from hexapod_adapt.online.mboa import Mboa, PROFILES
from hexapod_adapt.online.replay import lookup_trial
import numpy as np
from studies.tuning_set import TUNING_DAMAGES


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument('--archive', required=True)
    ap.add_argument('--cache-dir', required=True)
    ap.add_argument('--profile', default='thesis')
    args = ap.parse_args(argv)
    archive = load_archive(args.archive)
    niches, descriptors, prior = candidates(archive)
    rows = []
    for damage in TUNING_DAMAGES:
        c = ceiling(archive, damage, 'mujoco', args.cache_dir)
        trial = lookup_trial(c)
        opt = Mboa(descriptors, prior, replace(PROFILES[args.profile], max_trials=100))
        while opt.stop_reason().value == 'continue':
            i = opt.next_index()
            opt.observe(i, trial(int(niches[i])))
        best = opt.best()
        truth = c.best_index  # ceiling niches are the elites, in the same order
        rank_prior = int(np.sum(prior > prior[truth]))
        rows.append(
            (
                best.measured / c.best_speed,
                len(opt.trials),
                float(np.max(opt.mean)),
                c.best_speed,
                float(opt.mean[truth]),
                float(opt.std[truth]),
                rank_prior,
            )
        )
        print(
            f'{damage.label:32s} ratio {rows[-1][0]:.2f} trials {len(opt.trials):3d}'
            f'  stop: max GP mean {rows[-1][2]:.3f}, ceiling {c.best_speed:.3f};'
            f' best gait: GP {rows[-1][4]:.3f} +/- {rows[-1][5]:.3f}, prior rank {rank_prior}'
        )
    a = np.array(rows)
    print(
        f'medians: ratio {np.median(a[:, 0]):.3f}, trials {np.median(a[:, 1]):.1f},'
        f' max GP mean at the stop {np.median(a[:, 2]):.3f} m/s vs ceiling'
        f' {np.median(a[:, 3]):.3f} m/s; GP mean at the true best {np.median(a[:, 4]):.3f}'
        f' +/- {np.median(a[:, 5]):.3f}; its prior rank {np.median(a[:, 6]):.0f} of {len(prior)}'
    )
    return 0


if __name__ == '__main__':
    sys.exit(main())
