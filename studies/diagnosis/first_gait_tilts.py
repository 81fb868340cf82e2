# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The peak tilt of a blind run's first gait under a damage, on each engine (issue 67).

A blind run that names nothing first walks the gait fastest on average over the default
diagnosis bank's first hypotheses (the lifted legs; ``FirstGait.EXPECTED``). This walks that
gait (or ``--niches``) once under each one-leg damage of ``--kind`` on every engine, each at the
step its trials use (the map's own engine at the map's step, the others converged), untimed and
unguarded, and prints its peak tilt and whether it passes the trials' tip guard. It measures;
it chooses nothing.

    python -m studies.diagnosis.first_gait_tilts --kind locked

With ``--runs F.csv`` (a ``run_diagnosis`` CSV of one kind), it walks instead every trial that
tipped there once more under that run's damage on MuJoCo and DART, and counts the ones each
engine also tips, by when the run tipped it: its first trial, while naming nothing, named.
"""

from __future__ import annotations

import argparse
import ast
from collections import Counter
import csv
import math

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_ceilings, shipped_map
from hexapod_adapt.mapping.simulation import engine_of_map
from hexapod_adapt.online.adaptation import candidates, DEFAULT_TIP_GUARD
from hexapod_adapt.online.bank import DEFAULT_DIAGNOSIS_BANK, load_diagnosis_banks
from hexapod_adapt.online.diagnosis import HypothesisWalks
from hexapod_adapt.online.safety import record_tilt
from hexapod_adapt.online.session import blended_prior, diagnosis_plan
from hexapod_sim.damage import Damage
import numpy as np

ENGINES = ('mujoco', 'pybullet', 'dart')


def first_gait(archive) -> int:
    """Return the niche a blind run of the default bank walks first (no gait vetoed)."""
    bank, _ = load_diagnosis_banks(
        archive, engine_of_map(archive), [shipped_ceilings()], DEFAULT_DIAGNOSIS_BANK
    )
    plan = diagnosis_plan(archive, bank, safety=None)
    niches, _, map_prior = candidates(archive)
    return int(niches[int(np.argmax(blended_prior(plan, map_prior)))])


def tipped_elsewhere(archive, rows: list[dict[str, str]]) -> Counter:
    """Count a run CSV's tipped trials by when they tipped and whether MuJoCo and DART tip too."""
    guard = DEFAULT_TIP_GUARD
    walks = {engine: HypothesisWalks(archive, engine) for engine in ('mujoco', 'dart')}
    tally: Counter = Counter()
    for row in rows:
        legs = row['failed_legs']  # run_diagnosis writes '(1, 4)', run_experiment_cli '1 4'
        legs = ast.literal_eval(legs) if legs.startswith('(') else tuple(map(int, legs.split()))
        damage = Damage.of(row['damage_kind'], tuple(legs))
        niches = ast.literal_eval(row['trial_niches'])
        tipped = ast.literal_eval(row['trial_tipped'])
        named = row['named'].split('|') if row['named'] else [''] * len(niches)
        for k, (niche, fell) in enumerate(zip(niches, tipped)):
            if not fell:
                continue
            when = 'first trial' if k == 0 else ('named' if named[k - 1] else 'naming nothing')
            also = tuple(
                f'{engine} {"tips" if record_tilt(w(niche, damage)) > guard else "upright"}'
                for engine, w in walks.items()
            )
            tally[(when, *also)] += 1
    return tally


def main(argv: list[str] | None = None) -> int:
    """Print each gait's peak tilt under each one-leg damage of the kind, per engine."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--archive', default=str(shipped_map(DEFAULT_MAP)))
    parser.add_argument('--kind', default='locked', help='a one-leg damage kind (Damage.of)')
    parser.add_argument('--niches', type=int, nargs='*', help='default: the first gait')
    parser.add_argument('--runs', help="a run_diagnosis CSV: its tipped trials' gaits instead")
    args = parser.parse_args(argv)
    archive = load_archive(args.archive)
    if args.runs:
        with open(args.runs, newline='', encoding='utf-8') as f:
            tally = tipped_elsewhere(archive, list(csv.DictReader(f)))
        for key, count in sorted(tally.items()):
            print(f'{count:4d}  ' + ', '.join(key))
        print(f'{sum(tally.values()):4d}  tipped trials in all')
        return 0
    niches = args.niches or [first_gait(archive)]
    guard = math.degrees(DEFAULT_TIP_GUARD)
    walks = {engine: HypothesisWalks(archive, engine) for engine in ENGINES}
    print(f'peak tilt [deg] of each gait walked once per engine; past {guard:.0f} deg tips')
    print('gait  damage            ' + ''.join(f'{e:>10s}' for e in ENGINES))
    for niche in niches:
        damages = [Damage.lifted(())] + [Damage.of(args.kind, (leg,)) for leg in range(1, 7)]
        for damage in damages:
            cells = []
            for engine in ENGINES:
                record = walks[engine](niche, damage)
                tilt = math.inf if record is None else math.degrees(record_tilt(record))
                cells.append(f'{tilt:9.1f}' + ('*' if tilt > guard else ' '))
            print(f'{niche:5d} {damage.label:17s} ' + ''.join(cells), flush=True)
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
