# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
How sure the diagnosis should be: its posterior over fixed trials, tempered and not (issue 67).

Open loop, so that every setting sees the same trials: each damage of ``--kind`` (every
orientation of S1-S4) walks the map's ``--gaits`` fastest gaits on ``--engine`` at its converged
step (the record a run's trial gives, no foot contacts; ``--friction`` and, on MuJoCo,
``--compliance-slope`` make it a physics the hypotheses were not walked in); the same gaits are
walked under each of the kind's 21 hypotheses on the map's engine, as a run's diagnosis walks
them. Then, for each
temperature (the power each trial's likelihood is raised to) and each "none of these" deviation,
the posterior after 1, 2, ... trials, with the run's own damage in the hypotheses (it should be
named) and left out (nothing should be named: "none of these" leads, or no hypothesis holds the
naming threshold). Prints one row per setting and trial count:

    python -m studies.diagnosis.calibration --engine mujoco --kind no_tibia --gaits 3

``--kind all``: the 168 damages of every kind, each weighed against all of them (the bank of
every kind); ``--shipped-only``: the shipped weighing alone, with the runs named right by kind
and those that named the right legs with another kind.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from itertools import product

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
from hexapod_adapt.online.adaptation import recorded_trial
from hexapod_adapt.online.diagnosis import (
    feature_names,
    feature_noise,
    HypothesisWalks,
    signature,
    student_log_likelihood,
    Weighing,
)
from hexapod_adapt.online.session import NAME_THRESHOLD
from hexapod_sim import create_simulator, SimConfig
from hexapod_sim.damage import Damage, EXPERIMENT_KINDS
from hexapod_sim.scenarios import scenario
from hexapod_sim.variants import draw_variants, variant_config
import numpy as np

TEMPERATURES = (1.0, 0.5, 0.3, 0.2, 0.1)
NONE_DEVIATIONS = (1.5, 2.0, 2.5, 3.0)


def trial_physics(
    engine: str, friction: float | None = None, compliance_slope: float | None = None
) -> SimConfig:
    """Return ``engine``'s converged physics with the trials' friction and servo compliance."""
    trials = replace(SimConfig.converged(engine), friction=friction)
    if compliance_slope is not None:
        slope = replace(trials.engine_settings(), compliance_slope=compliance_slope)
        trials = replace(trials, mujoco=slope)
    return trials


def variant_physics(variant: str) -> SimConfig:
    """
    Return MuJoCo's converged physics, as ``variant`` changes it.

    ``fF``: foot friction F; ``sS``: servo compliance slope S; ``rN``: the physics variant drawn
    from seed N (:func:`hexapod_sim.variants.draw_variants`: friction, servos, latency, masses,
    floor at once); ``nN``: N physics steps per row, not converged (a larger gap to the
    hypotheses' walks: studies/engines, "No cheaper MuJoCo setting converges"); ``stock``: none.
    """
    if variant == 'stock':
        return trial_physics('mujoco')
    if variant.startswith('r'):
        return variant_config(trial_physics('mujoco'), draw_variants(1, int(variant[1:]))[0])
    if variant.startswith('f'):
        return trial_physics('mujoco', friction=float(variant[1:]))
    if variant.startswith('s'):
        return trial_physics('mujoco', compliance_slope=float(variant[1:]))
    if variant.startswith('n'):
        return trial_physics('mujoco').with_substeps(int(variant[1:]))
    raise SystemExit(f'unknown variant {variant!r}: stock, fF, sS, rN or nN')


def residuals(archive, damages, trials: SimConfig, gaits: list[int]) -> np.ndarray:
    """
    Return (damage, gait, hypothesis, feature) scaled mismatches; NaN where a walk failed.

    Damage d's trial of each gait on ``trials``' physics against the same gait under each
    damage of ``damages`` on the map's engine.
    """
    walks = HypothesisWalks(archive)
    noise = feature_noise(feature_names(False))
    sim = create_simulator(trials)
    out = np.full((len(damages), len(gaits), len(damages), len(noise)), np.nan)
    for d, damage in enumerate(damages):
        trial = recorded_trial(archive, damage, sim)
        for g, niche in enumerate(gaits):
            outcome = trial(niche)
            if outcome.record is None:
                continue
            seen = signature(outcome.record, False)
            for h, hypothesis in enumerate(damages):
                walk = walks(niche, hypothesis)
                if walk is not None:
                    out[d, g, h] = (seen - signature(walk, False)) / noise
    return out


def posteriors(r: np.ndarray, temperature: float, deviation: float, keep: np.ndarray):
    """Return the posterior over ``keep``'s hypotheses and none (last) after each trial."""
    n_features = r.shape[-1]
    none = student_log_likelihood(np.full(n_features, deviation))
    none_prior = Weighing().none_prior
    log = np.log(np.append(np.full(keep.sum(), (1 - none_prior) / keep.sum()), none_prior))
    out = []
    for g in range(r.shape[0]):
        update = np.full(len(log), none)
        for i, h in enumerate(np.flatnonzero(keep)):
            if np.isfinite(r[g, h]).all():
                update[i] = student_log_likelihood(r[g, h])
        log = log + temperature * update
        p = np.exp(log - log.max())
        out.append(p / p.sum())
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--engine', default='mujoco')
    parser.add_argument('--kind', default='no_tibia')
    parser.add_argument('--gaits', type=int, default=3)
    parser.add_argument('--archive', default=str(shipped_map(DEFAULT_MAP)))
    parser.add_argument(
        '--friction',
        type=float,
        default=None,
        help="the trials' foot friction (a physics variant)",
    )
    parser.add_argument(
        '--compliance-slope',
        type=float,
        default=None,
        help="MuJoCo trials: the servos' compliance slope (32 stock; larger is softer)",
    )
    parser.add_argument(
        '--shipped-only',
        action='store_true',
        help='the shipped weighing only, with a count by kind',
    )
    args = parser.parse_args(argv)
    trials = trial_physics(args.engine, args.friction, args.compliance_slope)
    archive = load_archive(args.archive)
    legs_all = [legs for name in ('S1', 'S2', 'S3', 'S4') for legs in scenario(name)]
    kinds = EXPERIMENT_KINDS if args.kind == 'all' else (args.kind,)
    damages = [Damage.of(kind, legs) for kind in kinds for legs in legs_all]
    kind_of = [kind for kind in kinds for _ in legs_all]
    elites = archive.elite_indices()
    gaits = [int(n) for n in elites[np.argsort(-archive.fitness[elites])][: args.gaits]]
    r = residuals(archive, damages, trials, gaits)
    n = len(damages)
    if args.shipped_only:
        _by_kind(r, damages, kind_of, len(gaits))
        return 0
    print('temperature none_dev trials | in bank: named right, named wrong | left out: named')
    for temperature, deviation in product(TEMPERATURES, NONE_DEVIATIONS):
        right = np.zeros(len(gaits), int)
        wrong = np.zeros(len(gaits), int)
        named_out = np.zeros(len(gaits), int)
        for d in range(n):
            everyone = np.ones(n, bool)
            for k, p in enumerate(posteriors(r[d], temperature, deviation, everyone)):
                lead = int(np.argmax(p))
                right[k] += lead == d and p[lead] >= NAME_THRESHOLD
                wrong[k] += lead not in (d, n) and p[lead] >= NAME_THRESHOLD
            others = everyone.copy()
            others[d] = False
            for k, p in enumerate(posteriors(r[d], temperature, deviation, others)):
                lead = int(np.argmax(p))
                named_out[k] += lead < n - 1 and p[lead] >= NAME_THRESHOLD
        for k in range(len(gaits)):
            print(
                f'{temperature:g} {deviation:g} {k + 1} | {right[k]} {wrong[k]} of {n}'
                f' | {named_out[k]} of {n}',
                flush=True,
            )
    return 0


def _by_kind(r: np.ndarray, damages: list[Damage], kind_of: list[str], n_gaits: int) -> None:
    """Print, per kind and trial count, the runs named right and those named on the right legs."""
    shipped = Weighing()
    everyone = np.ones(len(damages), bool)
    print('kind trials | named right | right legs, another kind | none or below the threshold')
    for kind in dict.fromkeys(kind_of):
        rows = [i for i, k in enumerate(kind_of) if k == kind]
        right = np.zeros(n_gaits, int)
        legs = np.zeros(n_gaits, int)
        for d in rows:
            ps = posteriors(r[d], shipped.temperature, shipped.none_deviation, everyone)
            for k, p in enumerate(ps):
                lead = int(np.argmax(p))
                named = lead < len(damages) and p[lead] >= NAME_THRESHOLD
                right[k] += named and lead == d
                same_legs = damages[lead].failed_legs == damages[d].failed_legs
                legs[k] += named and lead != d and same_legs
        for k in range(n_gaits):
            rest = len(rows) - right[k] - legs[k]
            print(f'{kind} {k + 1} | {right[k]} | {legs[k]} | {rest} of {len(rows)}', flush=True)


if __name__ == '__main__':
    raise SystemExit(main())
