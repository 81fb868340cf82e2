# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
r"""
Check cached ceilings against today's evaluation rules, for their fastest gaits.

Ceilings cached before falls were scored (a gait that ends upside down: 0) could hold a fall's
distance. For each cached ceiling of a map, re-evaluate its ``--top`` fastest gaits and report
any that differ; a ceiling (its best speed) stands if none of them does.

    python -m studies.adaptation.check_ceilings --archive hexapod_adapt/maps/default_map.npz \\
        --cache-dir hexapod_adapt/maps/ceilings --scenarios
"""

from __future__ import annotations

import argparse
import sys

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.online.ceiling import ceiling
from hexapod_sim import create_simulator, evaluate_gaits, SimConfig
from hexapod_sim.damage import Damage
from hexapod_sim.scenarios import scenario
import numpy as np
from studies.tuning_set import TUNING_DAMAGES


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument('--archive', required=True)
    ap.add_argument('--cache-dir', required=True)
    ap.add_argument('--scenarios', action='store_true', help='S1-S4 (else the tuning set)')
    ap.add_argument('--top', type=int, default=20)
    args = ap.parse_args(argv)
    archive = load_archive(args.archive)
    damages = (
        [Damage.lifted(legs) for name in ('S1', 'S2', 'S3', 'S4') for legs in scenario(name)]
        if args.scenarios
        else list(TUNING_DAMAGES)
    )
    differ = 0  # beyond 1e-6 m/s: machines differ in the last bits of floating point
    with create_simulator(SimConfig(engine='mujoco')) as sim:
        for damage in damages:
            c = ceiling(archive, damage, 'mujoco', args.cache_dir)
            order = np.argsort(-c.speeds)[: args.top]
            now = evaluate_gaits(
                list(archive.genotypes[c.niches[order]]),
                sim,
                duration=archive.trial_duration,
                collisions_fatal=False,
                failed_legs=damage,
            )
            bad = [
                (int(c.niches[i]), r.reason)
                for i, r in zip(order, now)
                if abs(r.speed - c.speeds[i]) > 1e-6
            ]
            differ += len(bad)
            print(f'{damage.label:32s} top {args.top}: {len(bad)} differ {bad[:3]}')
    print(
        f'{differ} of {len(damages) * args.top} fastest cached gaits differ from a new evaluation'
    )
    return 0 if differ == 0 else 1


if __name__ == '__main__':
    sys.exit(main())
