# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
r"""
How many gaits the streaming prior must score before the first trial (``TOP_FIRST``).

The first trial of a run with the damage-informed prior walks M-BOA's first pick (its UCB before
any trial is the prior mean plus a constant: the prior's best gait). When the damage has no cached
ceiling, the prior is a partial re-score
(:func:`hexapod_adapt.online.ceiling.estimate_unwalked`): the ``n`` fastest intact gaits scored
under the damage, the others estimated. For each case this replays that choice from the case's full
ceiling and reports the first gait's speed under the damage as a ratio of the ceiling, for each
``n``.

Tuning data: the default map's 21 ``unpowered_coxa`` cases (no reported figure depends on
``TOP_FIRST``: the reported prior runs read cached ceilings). Rule, fixed before the run: the
smallest ``n`` of 64, 128, 192 and 256 whose median and 10th-percentile ratio are each within
0.02 of n = 256's; 256 stays otherwise. The ``lifted`` cases are reported once, after the choice.

    python -m studies.adaptation.first_scored --kind unpowered_coxa
"""

from __future__ import annotations

import argparse
import sys

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import shipped_ceilings, shipped_map
from hexapod_adapt.mapping.simulation import engine_of_map
from hexapod_adapt.online.ceiling import cached_ceiling, estimate_unwalked
from hexapod_adapt.online.mboa import Mboa, PROFILES
from hexapod_sim.damage import Damage
from hexapod_sim.scenarios import scenario
import numpy as np

CANDIDATES = (64, 128, 192, 256)
TOLERANCE = 0.02


def first_pick_ratio(
    descriptors: np.ndarray, intact: np.ndarray, damaged: np.ndarray, n: int
) -> float:
    """Return the damaged speed of the first trial's gait after ``n`` are scored / the ceiling."""
    order = np.argsort(-intact, kind='stable')
    scored = np.full(len(intact), np.nan)
    scored[order[:n]] = damaged[order[:n]]
    pick = Mboa(descriptors, estimate_unwalked(intact, scored), PROFILES['default']).next_index()
    return float(damaged[pick] / damaged.max())


def main(argv: list[str] | None = None) -> int:
    """Print, for each n, the first pick's ratio over the kind's S1-S4 cases."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    ap.add_argument('--kind', default='unpowered_coxa')
    args = ap.parse_args(argv)
    archive = load_archive(shipped_map())
    engine = engine_of_map(archive)
    niches = archive.elite_indices()
    intact, descriptors = archive.speeds()[niches], archive.descriptors[niches]
    cases = [legs for name in ('S1', 'S2', 'S3', 'S4') for legs in scenario(name)]
    ratios: dict[int, list[float]] = {n: [] for n in CANDIDATES}
    for legs in cases:
        found = cached_ceiling(archive, Damage.of(args.kind, legs), engine, [shipped_ceilings()])
        if found is None:
            print(f'no cached ceiling for {args.kind} legs {legs}', file=sys.stderr)
            return 1
        for n in CANDIDATES:
            ratios[n].append(first_pick_ratio(descriptors, intact, found.speeds, n))
    print(f'{args.kind}: {len(cases)} cases, first pick / ceiling')
    print('n     median  p10    min')
    for n, r in ratios.items():
        print(f'{n:<5} {np.median(r):.3f}   {np.percentile(r, 10):.3f}  {np.min(r):.3f}')
    ref = ratios[CANDIDATES[-1]]
    chosen = next(
        n
        for n in CANDIDATES
        if np.median(ratios[n]) >= np.median(ref) - TOLERANCE
        and np.percentile(ratios[n], 10) >= np.percentile(ref, 10) - TOLERANCE
    )
    print(f'rule: n = {chosen}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
