# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Why our engines disagree (issue 49, deliverable 2): the same gaits, step by step, on each engine.

For a map's gaits (the shipped default map unless --archive: its --fastest fastest and --random
others, seed 0), intact, 5 s from standing, collisions not fatal, on every engine: the speed,
the feet on the ground, how well the servos track their targets (commanded minus achieved angle,
RMS per joint kind), how far the feet slip while on the ground (horizontal speed of a foot tip
that is on the ground this step and the last), the body's height and its largest tilt, and how
often a servo is at its stall torque. Prints one table of medians per engine and writes every
gait's row as CSV (--out).

    python -m studies.engines.engine_disagreement [--archive MAP] [--fastest 50] [--random 50] \
        [--out studies/out/engine_disagreement.csv]
"""

from __future__ import annotations

import argparse
import csv
from dataclasses import asdict, dataclass, replace
import math
import os
import time

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
from hexapod_adapt.mapping.transfer import ranked_gaits
from hexapod_description import N_LEGS
from hexapod_gait import build_joint_table, from_genotype
from hexapod_sim import create_simulator, ENGINES, SimConfig
from hexapod_sim.engine_settings import ACCURATE, PYBULLET_SERVOS
from hexapod_sim.simulator import peak_tilt, quat_to_matrix
import numpy as np

DURATION = 5.0


@dataclass(frozen=True)
class StepStats:
    """One gait walked on one engine."""

    engine: str
    niche: int
    map_speed: float  # m/s (the map's engine)
    speed: float  # m/s along the gait's crab angle
    feet_down: float  # mean feet on the ground
    track_coxa: float  # rad RMS, commanded - achieved
    track_femur: float
    track_tibia: float
    slip: float  # m/s: mean horizontal speed of feet on the ground
    height: float  # m: mean base height
    peak_tilt: float  # rad
    saturated: float  # fraction of servo-steps at the stall torque (within 1 %)
    peak_body_speed: float  # m/s: the base's fastest over any 0.1 s (a blown-up model flings it)


def walk(sim, genes: np.ndarray, niche: int, map_speed: float) -> StepStats:
    """Play one gait on ``sim`` step by step; measure it."""
    gait = from_genotype(genes)
    table = build_joint_table(gait, rate=1.0 / sim.dt)
    rows = sim.prepare_rows(table.positions, table.velocities)
    sim.set_failed_legs(())
    sim.reset(table.positions[0])
    n = int(round(DURATION / sim.dt))
    effort = np.array([lim.effort for lim in sim.model.limits])
    tibia = sim.model.tibia_length
    err = np.zeros((n, 18))
    feet = np.zeros((n, N_LEGS), dtype=bool)
    tips = np.zeros((n, N_LEGS, 3))
    base, quats = np.zeros((n, 3)), np.zeros((n, 4))
    saturated = 0
    for k in range(n):
        i = k % len(table.positions)
        sim.apply_row(rows, i)
        report = sim.step()
        q, _, torque = sim.joint_states()
        target = np.clip(table.positions[i], sim.lower, sim.upper)
        err[k] = target - q
        saturated += int(np.sum(np.abs(torque) >= 0.99 * effort))
        feet[k] = report.contacts
        poses = sim.link_poses()
        for leg in range(N_LEGS):
            pos, quat = poses[f'link_{leg + 1}_3']
            tips[k, leg] = pos + quat_to_matrix(quat)[:, 0] * tibia
        pos, quat = sim.base_pose()
        base[k], quats[k] = pos, quat
    down = feet[1:] & feet[:-1]
    moved = np.linalg.norm(np.diff(tips[:, :, :2], axis=0), axis=2) / sim.dt
    slip = float(moved[down].mean()) if down.any() else float('nan')
    window = max(1, int(round(0.1 / sim.dt)))
    peak_body_speed = float(np.linalg.norm(base[window:] - base[:-window], axis=1).max() / 0.1)
    pos, _ = sim.base_pose()
    speed = (pos[0] * math.cos(gait.crab_angle) + pos[1] * math.sin(gait.crab_angle)) / DURATION
    rms = np.sqrt((err**2).mean(axis=0)).reshape(N_LEGS, 3).mean(axis=0)
    return StepStats(
        sim.engine,
        niche,
        map_speed,
        float(speed),
        float(feet.sum(axis=1).mean()),
        float(rms[0]),
        float(rms[1]),
        float(rms[2]),
        slip,
        float(base[:, 2].mean()),
        peak_tilt(quats),
        saturated / (n * 18),
        peak_body_speed,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--archive', default=None, help='a map (default: the shipped default map)')
    parser.add_argument('--fastest', type=int, default=50)
    parser.add_argument('--random', type=int, default=50)
    parser.add_argument('--engines', nargs='+', choices=ENGINES, default=list(ENGINES))
    parser.add_argument('--out', default=None, help='CSV of every gait on every engine')
    parser.add_argument(
        '--pybullet-servo',
        choices=PYBULLET_SERVOS,
        default=ACCURATE.servo,
        help="PyBullet's servo model (docs/simulator.md, item 3 of 'Where the engines differ')",
    )
    args = parser.parse_args()
    archive = load_archive(args.archive or str(shipped_map(DEFAULT_MAP)))
    niches = ranked_gaits(archive, args.fastest, args.random, seed=0)
    speeds = archive.speeds()
    rows: list[StepStats] = []
    pybullet = replace(ACCURATE, servo=args.pybullet_servo)
    for engine in args.engines:
        t0 = time.monotonic()
        with create_simulator(SimConfig(engine=engine, pybullet=pybullet)) as sim:
            for niche in niches:
                rows.append(walk(sim, archive.genotypes[niche], int(niche), float(speeds[niche])))
        print(f'{engine}: {len(niches)} gaits in {time.monotonic() - t0:.0f} s', flush=True)
    fields = [f for f in StepStats.__dataclass_fields__ if f not in ('engine', 'niche')]
    print('| engine | ' + ' | '.join(fields) + ' |')
    print('|---' * (len(fields) + 1) + '|')
    for engine in args.engines:
        mine = [r for r in rows if r.engine == engine]
        cells = [f'{np.nanmedian([getattr(r, f) for r in mine]):.3f}' for f in fields]
        print(f'| {engine} | ' + ' | '.join(cells) + ' |')
    if args.out:
        tmp = f'{args.out}.tmp'
        with open(tmp, 'w', newline='') as f:
            writer = csv.DictWriter(f, fieldnames=list(StepStats.__dataclass_fields__))
            writer.writeheader()
            writer.writerows(asdict(r) for r in rows)
        os.replace(tmp, args.out)


if __name__ == '__main__':
    main()
