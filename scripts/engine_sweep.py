#!/usr/bin/env python3
# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Sweep MuJoCo settings against the PyBullet reference and print a markdown table.

    python scripts/engine_sweep.py [--map hexapod_adapt/maps/demo_map.npz]

For each setting: the servo gains it implies, the intact control tripod's speed (and its ratio
to PyBullet's), the Spearman correlation of fitness with PyBullet over the map's gaits
(collisions not fatal), the mean absolute duty-factor difference, and the time per evaluation
(batches of 8, this process). The first row is the default (studies/engines/README.md).
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path
import time

from hexapod_gait import preset
from hexapod_sim import create_simulator, evaluate_gait, evaluate_gaits, SimConfig
from hexapod_sim.engine_settings import DEFAULT_SETTINGS, MujocoSettings
from hexapod_sim.fidelity_table_cli import map_genotypes
import numpy as np
from scipy.stats import spearmanr

SWEEP: list[tuple[str, MujocoSettings]] = [
    ('default (compliance slope 32, factory)', DEFAULT_SETTINGS),
    ('compliance slope 4', replace(DEFAULT_SETTINGS, compliance_slope=4.0)),
    ('compliance slope 8', replace(DEFAULT_SETTINGS, compliance_slope=8.0)),
    ('compliance slope 16', replace(DEFAULT_SETTINGS, compliance_slope=16.0)),
    ('compliance slope 64', replace(DEFAULT_SETTINGS, compliance_slope=64.0)),
    ('compliance slope 128', replace(DEFAULT_SETTINGS, compliance_slope=128.0)),
    ('no back-EMF damping', replace(DEFAULT_SETTINGS, back_emf=False)),
    ('elliptic friction cone', replace(DEFAULT_SETTINGS, cone='elliptic')),
    ('5 solver iterations', replace(DEFAULT_SETTINGS, iterations=5)),
    ('armature 0.005 kg m^2', replace(DEFAULT_SETTINGS, armature=0.005)),
    ('softer contacts (time constant 0.04 s)', replace(DEFAULT_SETTINGS, contact_timeconst=0.04)),
    (
        'stiffer contacts (time constant 0.0084 s)',
        replace(DEFAULT_SETTINGS, contact_timeconst=0.0084),
    ),
]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument(
        '--map',
        type=Path,
        default=Path(__file__).resolve().parent.parent / 'hexapod_adapt' / 'maps' / 'demo_map.npz',
        help='archive whose gaits the engines are compared on',
    )
    args = ap.parse_args()
    genotypes = list(map_genotypes(args.map))
    with create_simulator(SimConfig(engine='pybullet')) as bullet:
        ref = evaluate_gaits(genotypes, bullet, collisions_fatal=False)
        tripod_ref = evaluate_gait(preset('control'), bullet, collisions_fatal=False).speed
    ref_speed = np.array([r.speed for r in ref])
    ref_desc = np.array([r.descriptor for r in ref])
    print(
        f'PyBullet reference: control tripod {tripod_ref:.3f} m/s; {len(genotypes)} gaits of'
        f' {args.map.name}\n'
    )
    print(
        '| setting | kp RX-28 / RX-64 (N m/rad) | tripod (m/s) | ratio | Spearman | descriptor MAD'
        ' | invalid | ms/eval |'
    )
    print('|---|---|---|---|---|---|---|---|')
    for label, settings in SWEEP:
        with create_simulator(SimConfig(engine='mujoco', mujoco=settings)) as sim:
            tripod = evaluate_gait(preset('control'), sim, collisions_fatal=False).speed
            t0 = time.perf_counter()
            res = [
                r
                for i in range(0, len(genotypes), 8)
                for r in evaluate_gaits(genotypes[slice(i, i + 8)], sim, collisions_fatal=False)
            ]
            ms = (time.perf_counter() - t0) / len(genotypes) * 1e3
        speed = np.array([r.speed if r.valid else np.nan for r in res])
        ok = np.isfinite(speed)
        rho = spearmanr(speed[ok], ref_speed[ok])[0]
        mad = np.abs(np.array([r.descriptor for r in res])[ok] - ref_desc[ok]).mean()
        kp = f'{settings.servo_kp(3.464):.1f} / {settings.servo_kp(5.194):.1f}'
        print(
            f'| {label} | {kp} | {tripod:.3f} | {tripod / tripod_ref:.3f} | {rho:.3f} | {mad:.3f} '
            f'| {int((~ok).sum())} | {ms:.1f} |',
            flush=True,
        )
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
