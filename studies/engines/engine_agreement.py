# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Does a randomised MuJoCo predict PyBullet? The engines' agreement on a map's gaits.

The question behind a transfer-aware map (studies/map_methods/README.md, "Which gaits the engines
agree on"): if the fastest gaits of a MuJoCo map that fall or stall on PyBullet also degrade when
MuJoCo's own parameters are perturbed, a map made under randomised MuJoCo would transfer, and
PyBullet could stay the held-out engine. For a map (a study map, never the default map): its 300
fastest gaits and 100 others at random (seed 0), intact, 5 s from rest, collisions not fatal, on
MuJoCo as the map was made, on six one-parameter MuJoCo variants, and on PyBullet. Printed: each
variant's rank agreement with nominal MuJoCo and with PyBullet; two robust scores (mean and minimum
over the seven MuJoCo runs); what the 10 and 50 best gaits of each score do on PyBullet; and the
gaits' commanded body velocity, duty factor and feet on the ground against the engines'
disagreement.

    python -m studies.engines.engine_agreement --archive studies/out/map_study/cma_mae_10000_s2.npz
"""

from __future__ import annotations

import argparse
from dataclasses import replace

from hexapod_adapt.mapping.archive import load_archive
from hexapod_gait import from_genotype
from hexapod_sim import create_simulator, evaluate_gaits, SimConfig
from hexapod_sim.engine_settings import DEFAULT_SETTINGS
from hexapod_sim.evaluation import FELL_OVER
import numpy as np
from scipy.stats import spearmanr

#: One MuJoCo parameter changed each: ground friction (nominal 1.0), the servos' compliance slope
#: (softer / stiffer, nominal 32), contact softness (time constant, nominal 0.02 s) and reflected
#: rotor inertia (nominal 0).
VARIANTS: dict[str, SimConfig] = {
    'mujoco': SimConfig(engine='mujoco'),
    'friction 0.6': SimConfig(engine='mujoco', friction=0.6),
    'friction 1.5': SimConfig(engine='mujoco', friction=1.5),
    'compliance 64': SimConfig(
        engine='mujoco', mujoco=replace(DEFAULT_SETTINGS, compliance_slope=64.0)
    ),
    'compliance 16': SimConfig(
        engine='mujoco', mujoco=replace(DEFAULT_SETTINGS, compliance_slope=16.0)
    ),
    'contact 0.05 s': SimConfig(
        engine='mujoco', mujoco=replace(DEFAULT_SETTINGS, contact_timeconst=0.05)
    ),
    'armature 0.01': SimConfig(engine='mujoco', mujoco=replace(DEFAULT_SETTINGS, armature=0.01)),
}
FASTEST = 300
RANDOM = 100


def speeds_on(config: SimConfig, genes: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Return (speeds [m/s], fell over) of the gaits on one engine and setting."""
    with create_simulator(config) as sim:
        results = evaluate_gaits(genes, sim, collisions_fatal=False)
    return np.array([r.speed for r in results]), np.array([r.reason == FELL_OVER for r in results])


def rho(a: np.ndarray, b: np.ndarray) -> float:
    """Spearman's rank correlation."""
    return float(spearmanr(a, b)[0])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--archive', required=True, help='a study or tuning map')
    args = parser.parse_args()
    archive = load_archive(args.archive)
    elites = archive.elite_indices()
    order = elites[np.argsort(-archive.speeds()[elites])]
    others = np.random.default_rng(0).choice(order[FASTEST:], RANDOM, replace=False)
    picked = np.concatenate([order[:FASTEST], others])
    genes = list(archive.genotypes[picked])
    print(f'map: {args.archive}: its {FASTEST} fastest gaits and {RANDOM} others at random')
    runs = {name: speeds_on(config, genes) for name, config in VARIANTS.items()}
    pybullet, fell = speeds_on(SimConfig(engine='pybullet'), genes)
    top = slice(0, FASTEST)
    nominal = runs['mujoco'][0]
    print(
        f'PyBullet: speed median {np.median(pybullet):.3f} m/s (the {FASTEST} fastest:'
        f' {np.median(pybullet[top]):.3f}), {int(fell.sum())} fell over'
    )
    print('setting          median   Spearman vs MuJoCo   vs PyBullet (all / fastest)   falls')
    for name, (speeds, falls) in runs.items():
        print(
            f'{name:15s}  {np.median(speeds):.3f}    {rho(speeds, nominal):6.3f}'
            f'               {rho(speeds, pybullet):6.3f} / {rho(speeds[top], pybullet[top]):6.3f}'
            f'              {int(falls.sum())}'
        )
    table = np.stack([s for s, _ in runs.values()])
    scores = {
        'map speed': archive.speeds()[picked],
        'MuJoCo': nominal,
        'mean of 7': table.mean(axis=0),
        'min of 7': table.min(axis=0),
    }
    print('score        vs PyBullet   best 10 on PyBullet (median, falls)   best 50')
    for name, score in scores.items():
        line = f'{name:11s}  {rho(score, pybullet):6.3f}'
        for k in (10, 50):
            best = np.argsort(-score)[:k]
            line += f'        {np.median(pybullet[best]):6.3f}, {int(fell[best].sum()):2d}'
        print(line)
    gaits = [from_genotype(g) for g in genes]
    features = {
        'commanded body velocity': np.array([g.body_velocity for g in gaits]),
        'duty factor (mean of legs)': np.array([g.duty_factor.mean() for g in gaits]),
        'step height (mean)': np.array([g.step_height.mean() for g in gaits]),
        'feet on the ground (MuJoCo)': archive.descriptors[picked].sum(axis=1),
    }
    print('feature                       median (fastest)   Spearman vs PyBullet - MuJoCo')
    for name, value in features.items():
        disagreement = rho(value, pybullet - nominal)
        print(f'{name:28s}  {np.median(value[top]):.3f}              {disagreement:6.3f}')


if __name__ == '__main__':
    main()
