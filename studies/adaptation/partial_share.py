# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
How much of a map a ceiling must walk: where each damage's fastest gait lies in the intact order.

For every full ceiling of the map cached (the 8 kinds' S1-S4 cases, or ``--kinds``), the rank of
its fastest damaged gait among the map's gaits by intact speed, and for each share F of the map
walked intact-fastest first (a partial ceiling, ``hexapod_adapt.online.ceiling.TOP_FRACTION``):
the cases whose fastest gait lies within F, the cases whose prior (the rest estimated, as
``estimate_unwalked`` does) puts another gait first, and how many of the 10 fastest damaged gaits
the estimated prior keeps among its 10 first. No simulation.

    python -m studies.adaptation.partial_share                          # the shipped map
    python -m studies.adaptation.partial_share --archive M --ceilings DIR --kinds lifted
    python -m studies.adaptation.partial_share --check   # exit 1: a case deeper than the share
"""

from __future__ import annotations

import argparse
from pathlib import Path

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_ceilings, shipped_map
from hexapod_adapt.online.ceiling import (
    cached_ceiling,
    deepest_share,
    estimate_unwalked,
    intact_order,
    TOP_FRACTION,
)
from hexapod_sim.damage import Damage, EXPERIMENT_KINDS
from hexapod_sim.scenarios import scenario
import numpy as np

SHARES = (0.2, 0.3, 0.4, 0.5)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    ap.add_argument('--archive', type=Path, default=None, help='map (default: the shipped one)')
    ap.add_argument('--ceilings', type=Path, default=None, help='its full ceilings')
    ap.add_argument('--kinds', nargs='+', choices=EXPERIMENT_KINDS, default=list(EXPERIMENT_KINDS))
    ap.add_argument(
        '--check',
        action='store_true',
        help=f'exit 1 if a fastest damaged gait lies past the intact-fastest {TOP_FRACTION:.0%}%',
    )
    args = ap.parse_args()
    archive = load_archive(args.archive or shipped_map(DEFAULT_MAP))
    dirs = [args.ceilings or shipped_ceilings()]
    intact = archive.speeds()[archive.elite_indices()]
    order = intact_order(archive)
    rank_of = np.empty(len(order), int)
    rank_of[order] = np.arange(len(order))
    cases = []
    for kind in args.kinds:
        for name in ('S1', 'S2', 'S3', 'S4'):
            for legs in scenario(name):
                c = cached_ceiling(archive, Damage.of(kind, legs), 'mujoco', dirs)
                if c is not None and c.walked is None:
                    cases.append((kind, c))
    if not cases:
        raise SystemExit(f'no full ceiling of the map in {dirs[0]}')
    ranks = np.array([rank_of[c.best_index] for _, c in cases])
    print(f'{len(cases)} full ceilings, {len(intact)} gaits; the fastest damaged gait at intact')
    print(
        f'rank median {np.median(ranks):.0f}, largest {ranks.max()}'
        f' ({ranks.max() / len(intact):.1%})'
    )
    for kind in dict.fromkeys(k for k, _ in cases):
        mine = [r for (k, _), r in zip(cases, ranks) if k == kind]
        print(f'  {kind}: median {np.median(mine):.0f}, largest {max(mine)}')
    deepest = np.argsort(-ranks, kind='stable')[:3]
    print('deepest: ' + '; '.join(f'{cases[i][1].damage.label} ({ranks[i]})' for i in deepest))
    print(
        '| share walked | fastest within | prior puts another first | top-10 kept: median, least |'
    )
    print('|---|---|---|---|')
    for share in SHARES:
        walk = order[: int(np.ceil(share * len(intact)))]
        within = int(np.sum(ranks < len(walk)))
        other, kept = 0, []
        for _, c in cases:
            speeds = c.speeds
            part = np.full(len(speeds), np.nan)
            part[walk] = speeds[walk]
            prior = estimate_unwalked(intact, part)
            other += int(np.argmax(prior) != np.argmax(speeds))
            kept.append(len(set(np.argsort(-speeds)[:10]) & set(np.argsort(-prior)[:10])))
        print(
            f'| {share:.0%} | {within} / {len(cases)} | {other}'
            f' | {np.median(kept):.0f}, {min(kept)} |'
        )
    share = deepest_share(archive, [c for _, c in cases])
    if args.check and share > TOP_FRACTION:
        print(f'a fastest gait lies at {share:.1%} of the intact order, past {TOP_FRACTION:.0%}')
        return 1
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
