# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
What naming the kind is worth once the legs are known: the bank's re-scores, kind against kind.

For each pair of damage kinds (A, B) and each of the 21 leg sets of S1-S4, from the shipped
ceilings (the default map re-scored under each damage on its engine): how alike the two
re-scores rank the map (Spearman), and what a run loses that takes B for A: A's best speed
minus A's speed of B's best gait. Each cell prints the medians over the leg sets,
``spearman/loss`` (m/s). No simulation: the cached re-scores only.

Both are taken over the gaits every case walks: the map's intact-fastest share (``partial_share``)
(a partial case estimates the rest from their intact speeds, which would agree by construction).
``--kinds`` limits the table to kinds whose 21 cases are cached.

    python -m studies.diagnosis.kind_equivalence [--kinds lifted locked ...]
"""

from __future__ import annotations

import argparse

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_ceilings, shipped_map
from hexapod_adapt.mapping.simulation import engine_of_map
from hexapod_adapt.online.bank import load_bank
from hexapod_adapt.online.ceiling import partial_share
from hexapod_sim.damage import Damage, EXPERIMENT_KINDS
from hexapod_sim.scenarios import scenario
import numpy as np
from scipy.stats import spearmanr


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('--kinds', nargs='+', choices=EXPERIMENT_KINDS, default=EXPERIMENT_KINDS)
    kinds = tuple(parser.parse_args(argv).kinds)
    archive = load_archive(shipped_map(DEFAULT_MAP))
    leg_sets = [legs for name in ('S1', 'S2', 'S3', 'S4') for legs in scenario(name)]
    damages = [Damage.of(kind, legs) for kind in kinds for legs in leg_sets]
    bank = load_bank(archive, engine_of_map(archive), [shipped_ceilings()], damages)
    if bank.missing:
        print(f'not cached: {[d.label for d in bank.missing]}')
        return 1
    row_of = {d: i for i, d in enumerate(bank.damages)}
    walked = partial_share(archive)  # positions in bank.speeds' columns (the elites' order)
    print(f'over the intact-fastest {len(walked)} of {len(archive.elite_indices())} gaits')
    print(f'{"taken for ->":>15s}', ' '.join(f'{k:>16s}' for k in kinds))
    for true in kinds:
        cells = []
        for taken in kinds:
            rho, loss = [], []
            for legs in leg_sets:
                a = bank.speeds[row_of[Damage.of(true, legs)]][walked]
                b = bank.speeds[row_of[Damage.of(taken, legs)]][walked]
                rho.append(spearmanr(a, b)[0])
                loss.append(a.max() - a[int(np.argmax(b))])
            cells.append(f'{np.median(rho):.2f}/{np.median(loss):.3f}')
        print(f'{true:>15s}', ' '.join(f'{c:>16s}' for c in cells))
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
