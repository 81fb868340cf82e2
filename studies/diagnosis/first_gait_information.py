# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A first gait that tells the hypotheses apart: an open-loop probe (issue 67, deliverable 1).

A blind run's first gait is the fastest on average over the lifted bank's 21 hypotheses
(``FirstGait.EXPECTED``). Issue 67 says it may be chosen to tell them apart too. This probe asks
whether that could pay, before any rule is built: for each of the ``--top`` gaits the bank
expects fastest, it

- walks the gait under each hypothesis on the map's engine (as the diagnosis does) and scores
  how well one trial of it tells them apart by the walks alone (``Diagnosis.separation``: the
  posterior the truth would get were the trial its own walk, averaged over the hypotheses);
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
    HypothesisWalks,
)
from hexapod_adapt.online.session import blended_prior, diagnosis_plan
from hexapod_sim import create_simulator
import numpy as np
from studies.diagnosis.calibration import variant_physics


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--top', type=int, default=20)
    parser.add_argument('--variants', nargs='+', default=['s16', 's64', 's128'])
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
    labels = tuple(d.label for d in damages)
    header = ['gait', 'expected m/s', 'separation']
    header += [f'{v} named / p(truth)' for v in args.variants]
    print(' | '.join(header), flush=True)
    t0 = time.monotonic()
    for index in order:
        niche = int(niches[index])
        apart = plan.diagnosis.separation(niche)  # before any trial: the prior's weights
        cells = [str(niche), f'{expected[index]:.3f}', f'{apart:.3f}']
        for v, sim in sims.items():
            named, truth = 0, []
            for h, damage in enumerate(damages):
                outcome = recorded_trial(archive, damage, sim)(niche)
                if outcome.record is None:
                    truth.append(0.0)
                    continue
                diagnosis = Diagnosis(labels, walks.under(damages))
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
