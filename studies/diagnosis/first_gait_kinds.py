# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
What a blind run's first gait walks under each damage kind: why locked legs start slow.

A blind run's first trial walks the gait the bank expects fastest over its hypotheses
(``FirstGait.EXPECTED``, ``blended_prior``), whatever the damage. This reads what that gait
walked in each cached S1-S4 case (the shipped ceilings), kind by kind, beside the gait a kind
would want first (the best mean over its own cases) and, for ``--worst`` (default: the kind the
first gait serves worst), the trade-off: the best mean over the other kinds of a gait that walks
at least F m/s on that kind. No simulation; kinds with fewer than 21 cases cached are left out.

    python -m studies.diagnosis.first_gait_kinds
"""

from __future__ import annotations

import argparse

from hexapod_adapt.mapping.archive import Archive, load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_ceilings, shipped_map
from hexapod_adapt.online.bank import load_bank
from hexapod_adapt.online.ceiling import cached_ceiling
from hexapod_adapt.online.session import blended_prior, diagnosis_plan
from hexapod_sim.damage import Damage, EXPERIMENT_KINDS
from hexapod_sim.scenarios import scenario
import numpy as np

FLOORS = (0.05, 0.10, 0.15, 0.20)


def kind_means(archive: Archive, kinds: list[str]) -> dict[str, np.ndarray]:
    """Each kind's mean speed of every gait over its 21 cases (NaN: a gait some case skipped)."""
    dirs = [shipped_ceilings()]
    means = {}
    for kind in kinds:
        cases = [
            cached_ceiling(archive, Damage.of(kind, legs), 'mujoco', dirs)
            for name in ('S1', 'S2', 'S3', 'S4')
            for legs in scenario(name)
        ]
        if any(c is None for c in cases):
            continue
        speeds = np.array([np.where(c.walked_mask, c.speeds, np.nan) for c in cases])
        means[kind] = speeds.mean(axis=0)
    return means


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--worst', choices=EXPERIMENT_KINDS, default=None)
    args = parser.parse_args(argv)
    archive = load_archive(shipped_map(DEFAULT_MAP))
    bank = load_bank(archive, 'mujoco', [shipped_ceilings()])
    plan = diagnosis_plan(archive, bank)
    niches = archive.elite_indices()
    intact = archive.speeds()[niches]
    first = int(np.argmax(blended_prior(plan, intact)))
    means = kind_means(archive, list(EXPERIMENT_KINDS))
    if not means:
        raise SystemExit('no kind has its 21 ceilings cached')
    print(f'first gait: niche {int(niches[first])} (intact {intact[first]:.3f} m/s)')
    print('| kind | first gait, mean of 21 cases | best single gait for the kind |')
    print('|---|---|---|')
    for kind, m in means.items():
        print(f'| {kind} | {m[first]:.3f} | {np.nanmax(m):.3f} |')
    worst = args.worst or min(means, key=lambda k: means[k][first])
    others = [k for k in means if k != worst]
    if worst not in means or not others:
        return 0
    rest = np.array([means[k] for k in others]).mean(axis=0)
    print(f'\n| {worst} at least | best gait: {worst}, mean of {", ".join(others)} |')
    print('|---|---|')
    for floor in FLOORS:
        fits = np.where(means[worst] >= floor, rest, np.nan)
        if np.all(np.isnan(fits)):
            print(f'| {floor:.2f} | none |')
            continue
        g = int(np.nanargmax(fits))
        print(f'| {floor:.2f} | {means[worst][g]:.3f}, {rest[g]:.3f} |')
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
