# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A first gait that tells the hypotheses apart: an open-loop probe (issue 67, deliverable 1).

A blind run's first gait is the fastest on average over the lifted bank's 21 hypotheses
(``FirstGait.EXPECTED``). Issue 67 says it may be chosen to tell them apart too. This probe asks
whether that could pay, before any rule is built: for each of the ``--top`` gaits the bank
expects fastest, it

- walks the gait under each hypothesis on the map's engine (as the diagnosis does) and scores
  how well one trial of it tells them apart by the walks alone: the mean, over the hypotheses
  taken as the truth, of the posterior the diagnosis gives the truth when the trial is its own
  walk with each feature moved by ``--shift`` noise scales (``separation``);
- walks it under each of the 21 damages in each ``--variants`` physics (MuJoCo trials at its
  converged step, a servo softer or stiffer: studies/diagnosis/README.md, "The servo's range as
  a tuning set"), and counts the trials after which the diagnosis's leader is the true damage.

Only MuJoCo takes part: the judge (DART) and PyBullet measure a rule, once, if one follows. The
safety model's veto of the first gait is left out (every trial is walked). Prints one row per
gait, best expected first:

    python -m studies.diagnosis.first_gait_information --top 20 --variants s16 s64 s128
"""

from __future__ import annotations

import argparse
import time

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_ceilings, shipped_map
from hexapod_adapt.online.adaptation import recorded_trial
from hexapod_adapt.online.bank import load_bank
from hexapod_adapt.online.diagnosis import (
    Diagnosis,
    feature_names,
    feature_noise,
    HypothesisWalks,
    signature,
    student_log_likelihood,
)
from hexapod_adapt.online.session import blended_prior, diagnosis_plan
from hexapod_sim import create_simulator
import numpy as np
from studies.diagnosis.calibration import variant_physics


def own_posterior(walks: list) -> float:
    """Return the mean posterior of the truth when each hypothesis's own walk is the trial."""
    noise = feature_noise(feature_names(False))
    sigs = [None if w is None else signature(w, False) for w in walks]
    scores = []
    for own in sigs:
        if own is None:
            scores.append(0.0)
            continue
        ll = np.array(
            [
                -np.inf if other is None else student_log_likelihood((own - other) / noise)
                for other in sigs
            ]
        )
        scores.append(float(1.0 / np.sum(np.exp(ll - student_log_likelihood(0 * own)))))
    return float(np.mean(scores))


def separation(walks: list, shift: float) -> float:
    """
    Return the mean posterior of the truth when each hypothesis's own walk is the trial.

    Each feature of the trial is moved by ``shift`` noise scales, in the direction that brings
    it nearest another hypothesis (the worst case of a trial off its own walk); "none of these"
    is left out. A walk that cannot be made counts as a posterior of 0.
    """
    names = feature_names(False)
    noise = feature_noise(names)
    sigs = [None if w is None else signature(w, False) for w in walks]
    scores = []
    for h, own in enumerate(sigs):
        if own is None:
            scores.append(0.0)
            continue
        worst = 1.0
        for k, other in enumerate(sigs):
            if k == h or other is None:
                continue
            toward = np.clip((other - own) / noise, -shift, shift)
            seen = own + toward * noise
            ll_h = student_log_likelihood((seen - own) / noise)
            ll_k = student_log_likelihood((seen - other) / noise)
            worst = min(worst, 1.0 / (1.0 + np.exp(ll_k - ll_h)))
        scores.append(worst)
    return float(np.mean(scores))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--top', type=int, default=20)
    parser.add_argument('--variants', nargs='+', default=['s16', 's64', 's128'])
    parser.add_argument('--shift', type=float, default=1.0)
    parser.add_argument('--workers', type=int, default=1)
    args = parser.parse_args(argv)
    archive = load_archive(shipped_map(DEFAULT_MAP))
    bank = load_bank(archive, 'mujoco', [shipped_ceilings()])  # the 21 lifted leg sets
    damages = list(bank.damages)
    walks = HypothesisWalks(archive, 'mujoco', args.workers)
    plan = diagnosis_plan(archive, bank, walks=walks)
    niches = archive.elite_indices()
    expected = blended_prior(plan, archive.speeds()[niches])
    order = np.argsort(-expected, kind='stable')[: args.top]
    sims = {v: create_simulator(variant_physics(v)) for v in args.variants}
    header = ['gait', 'expected m/s', 'own posterior', f'separation@{args.shift:g}']
    header += [f'{v} named / p(truth)' for v in args.variants]
    print(' | '.join(header), flush=True)
    t0 = time.monotonic()
    for index in order:
        niche = int(niches[index])
        walks.prefetch((niche, d) for d in damages)
        own = [walks(niche, d) for d in damages]
        sep = separation(own, args.shift)
        cells = [str(niche), f'{expected[index]:.3f}', f'{own_posterior(own):.3f}', f'{sep:.3f}']
        for v, sim in sims.items():
            named, truth = 0, []
            for h, damage in enumerate(damages):
                outcome = recorded_trial(archive, damage, sim)(niche)
                if outcome.record is None:
                    truth.append(0.0)
                    continue
                diagnosis = Diagnosis(tuple(d.label for d in damages), walks.under(damages))
                p = diagnosis.observe(niche, outcome.record).probabilities
                named += int(np.argmax(p) == h)
                truth.append(float(p[h]))
            cells.append(f'{named} / {np.mean(truth):.2f}')
        print(' | '.join(cells), f'({time.monotonic() - t0:.0f} s)', flush=True)
    for sim in sims.values():
        sim.close()
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
