# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
How a map's gaits fare off the engine that made them (the default map's transfer risk).

For a map (the shipped default map unless --archive): its 100 fastest gaits and 200 different
gaits at random (seed 0) evaluated intact on PyBullet from rest (5 s, collisions not fatal),
counting falls (ended on the back) and the median speed; then its 20 fastest gaits walked one
after another on the emulated robot (ConsecutiveTrials, Xsens-like noise, seed 5) on each
engine: the IMU odometry's worst and RMS error against the truth, and how many trials ended
upside down.

    python -m studies.transfer.map_transfer [--archive MAP]  # results/map_transfer.txt
"""

from __future__ import annotations

import argparse

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
from hexapod_bridge.emulator.consecutive import ConsecutiveTrials
from hexapod_gait import from_genotype
from hexapod_sim import create_simulator, evaluate_gaits, SimConfig
from hexapod_sim.evaluation import FELL_OVER
from hexapod_sim.simulator import upside_down
import numpy as np


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--archive', default=None, help='a map (default: the shipped default map)')
    args = parser.parse_args()
    path = args.archive or str(shipped_map(DEFAULT_MAP))
    archive = load_archive(path)
    elites = archive.elite_indices()
    speeds = archive.speeds()
    order = elites[np.argsort(-speeds[elites])]
    print(f'map: {path} ({len(elites)} gaits)')
    rng = np.random.default_rng(0)
    with create_simulator(SimConfig(engine='pybullet')) as sim:
        random = rng.choice(elites, 200, replace=False)  # 200 different gaits
        for label, idx in (('fastest 100', order[:100]), ('random 200', random)):
            res = evaluate_gaits(list(archive.genotypes[idx]), sim, collisions_fatal=False)
            falls = sum(r.reason == FELL_OVER for r in res)
            print(
                f'{label}: map (MuJoCo) speed median {np.median(speeds[idx]):.3f} m/s; on'
                f' PyBullet from rest: {falls} fell over, speed median'
                f' {np.median([r.speed for r in res]):.3f} m/s',
                flush=True,
            )
    for engine in ('mujoco', 'pybullet'):
        with create_simulator(SimConfig(engine=engine)) as sim:
            robot = ConsecutiveTrials(sim, seed=5)
            errors, flipped = [], 0
            for niche in order[:20]:
                truth, estimate = robot.trial(from_genotype(archive.genotypes[niche]))
                errors.append(abs(estimate - truth))
                flipped += upside_down(sim.base_pose()[1])
        print(
            f'20 fastest walked one after another on {engine}: odometry error max'
            f' {max(errors):.3f} m/s, RMS {np.sqrt(np.mean(np.square(errors))):.3f};'
            f' {flipped} of 20 ended upside down',
            flush=True,
        )


if __name__ == '__main__':
    main()
