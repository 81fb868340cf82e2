# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The diagnosis's feature noise, measured: how far a trial lies from its own hypothesis (issue 67).

``FEATURE_NOISE`` says how far a trial's feature may lie from the same gait simulated under the
true damage on the map's engine; its values were set by judgement. This measures it: each
damage of ``--kind`` (every orientation of S1-S4) walks ``--gaits`` gaits (drawn with ``--seed``
from the map's 300 intact-fastest) on MuJoCo at its converged step in ``--variants`` physics
variants drawn from ``--seed`` (:func:`hexapod_sim.variants.draw_variants`: friction, servos,
latency, masses and floor at once, within issue 66's ranges), and under its own damage on the
map's engine as the diagnosis walks it. Only MuJoCo takes part (the judge and PyBullet measure).
Prints, per feature, the shipped scale and the gap's robust scale (median |gap| / 0.6745), its
RMS and its 90th percentile of |gap|:

    python -m studies.diagnosis.noise_scales --variants 12 --gaits 8 --seed 67
"""

from __future__ import annotations

import argparse

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
from hexapod_adapt.online.adaptation import recorded_trial
from hexapod_adapt.online.diagnosis import feature_names, feature_noise, HypothesisWalks, signature
from hexapod_sim import create_simulator
from hexapod_sim.damage import Damage
from hexapod_sim.scenarios import scenario
from hexapod_sim.variants import draw_variants, variant_config
import numpy as np
from studies.diagnosis.calibration import trial_physics

#: A normal distribution's median |x| in standard deviations.
MAD_TO_SIGMA = 0.6745


def gaps(archive, damages: list[Damage], variants, gaits: list[int]) -> np.ndarray:
    """Return the (variant, damage, gait, feature) gaps, trial less hypothesis; NaN: not walked."""
    walks = HypothesisWalks(archive)
    n = len(feature_names(False))
    out = np.full((len(variants), len(damages), len(gaits), n), np.nan)
    for v, variant in enumerate(variants):
        sim = create_simulator(variant_config(trial_physics('mujoco'), variant))
        for d, damage in enumerate(damages):
            trial = recorded_trial(archive, damage, sim)
            for g, niche in enumerate(gaits):
                outcome = trial(niche)
                walk = walks(niche, damage)
                if outcome.record is None or walk is None:
                    continue
                out[v, d, g] = signature(outcome.record, False) - signature(walk, False)
        print(f'variant {v + 1} of {len(variants)} walked', flush=True)
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--kind', default='lifted')
    parser.add_argument('--variants', type=int, default=12)
    parser.add_argument('--gaits', type=int, default=8)
    parser.add_argument('--seed', type=int, default=67)
    parser.add_argument('--archive', default=str(shipped_map(DEFAULT_MAP)))
    parser.add_argument('--out', default=None, help='an .npz of the gaps (variant, damage, gait)')
    args = parser.parse_args(argv)
    archive = load_archive(args.archive)
    damages = [
        Damage.of(args.kind, legs) for name in ('S1', 'S2', 'S3', 'S4') for legs in scenario(name)
    ]
    elites = archive.elite_indices()
    fastest = elites[np.argsort(-archive.fitness[elites])][:300]
    rng = np.random.default_rng(args.seed)
    gaits = [int(n) for n in rng.choice(fastest, size=args.gaits, replace=False)]
    variants = draw_variants(args.variants, args.seed)
    gap = gaps(archive, damages, variants, gaits)
    if args.out:
        np.savez(args.out, gap=gap, gaits=np.array(gaits))
    flat = gap.reshape(-1, gap.shape[-1])
    flat = flat[np.isfinite(flat).all(axis=1)]
    names = feature_names(False)
    print(f'{len(flat)} walks; feature, shipped, robust scale, RMS, 90th percentile |gap|')
    for name, shipped, column in zip(names, feature_noise(names), flat.T):
        robust = np.median(np.abs(column)) / MAD_TO_SIGMA
        rms = np.sqrt(np.mean(np.square(column)))
        p90 = np.quantile(np.abs(column), 0.9)
        print(f'{name} {shipped:.4f} {robust:.4f} {rms:.4f} {p90:.4f}')
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
