# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Does a screened gait tilt more on physics it was not screened in? A tip margin (issue 67).

A run that names its damage walks the fastest gaits of that damage's re-score that its tip screen
lets through (their tilt, walked on the map's engine at the map's step, within the trials' tip
guard). For each damage of ``--kinds`` (every leg set of S1-S4), this takes the ``--gaits`` first
such gaits and walks each once more in a MuJoCo ``--variant`` physics (``s64``, ``f0.6``: see
``calibration.variant_physics``), at the converged step, untimed and unguarded, and records its
peak tilt. It prints, for each candidate margin, how many of the gaits a screen with that margin
lets through tip past the guard in the variant, and the median speed (re-score) the fastest gait
let through loses against no margin. MuJoCo only: PyBullet and DART take no part in choosing.
One CSV row per gait (``--out``).

    python -m studies.diagnosis.tilt_gap --variant s64 --out /tmp/tilt_gap_s64.csv
"""

from __future__ import annotations

import argparse
import csv
import math

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_ceilings, shipped_map
from hexapod_adapt.mapping.simulation import engine_of_map
from hexapod_adapt.online.adaptation import DEFAULT_TIP_GUARD
from hexapod_adapt.online.bank import load_bank
from hexapod_adapt.online.prior import simulated_tilts, TipScreen
from hexapod_sim import create_simulator
from hexapod_sim.damage import Damage, EXPERIMENT_KINDS
from hexapod_sim.scenarios import scenario
from hexapod_sim.simulator import peak_tilt
from hexapod_sim.traces import trace_gait
import numpy as np
from studies.diagnosis.calibration import variant_physics

MARGINS_DEG = (0.0, 2.5, 5.0, 7.5, 10.0, 15.0)
#: how far down a re-score the screen looks for the fastest gait within the widest margin
SEARCH = 400


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--variant', default='s64')
    parser.add_argument('--kinds', nargs='+', default=list(EXPERIMENT_KINDS))
    parser.add_argument('--gaits', type=int, default=5)
    parser.add_argument('--out', required=True)
    args = parser.parse_args(argv)
    archive = load_archive(shipped_map(DEFAULT_MAP))
    engine = engine_of_map(archive)
    legs_all = [legs for name in ('S1', 'S2', 'S3', 'S4') for legs in scenario(name)]
    damages = [Damage.of(kind, legs) for kind in args.kinds for legs in legs_all]
    bank = load_bank(archive, engine, [shipped_ceilings()], damages)
    if bank.missing:
        raise SystemExit(f'not cached: {[d.label for d in bank.missing]}')
    niches = archive.elite_indices()
    guard = DEFAULT_TIP_GUARD
    rows, lost = [], {m: [] for m in MARGINS_DEG}
    with create_simulator(variant_physics(args.variant)) as sim:
        for h, damage in enumerate(bank.damages):
            screen = TipScreen(simulated_tilts(archive, damage, engine), guard)
            passed = _screened(screen, bank.speeds[h], args.gaits)
            for m in MARGINS_DEG:
                within = [p for p in passed if screen.tilts[p] <= guard - math.radians(m)]
                if passed and within:
                    lost[m].append(bank.speeds[h][passed[0]] - bank.speeds[h][within[0]])
            for p in passed[: args.gaits]:
                trace = trace_gait(
                    archive.genotypes[niches[p]], sim, damage, archive.trial_duration, every=1
                )
                variant = math.pi if trace is None else peak_tilt(trace.quaternion)
                rows.append((damage.label, p, screen.tilts[p], variant))
            print(f'{damage.label}: {len(passed[: args.gaits])} gaits', flush=True)
    with open(args.out, 'w', newline='', encoding='utf-8') as f:
        writer = csv.writer(f)
        writer.writerow(['damage', 'position', 'screen_tilt', 'variant_tilt'])
        writer.writerows(rows)
    screen_tilt = np.array([r[2] for r in rows])
    tips = np.array([r[3] > guard for r in rows])
    print(f'variant {args.variant}: {len(rows)} gaits, {int(tips.sum())} tip in it')
    for m in MARGINS_DEG:
        through = screen_tilt <= guard - math.radians(m)
        print(
            f'margin {m:4.1f} deg: {int(through.sum())} let through, {int(tips[through].sum())}'
            f' of them tip; fastest let through loses a median {np.median(lost[m]):.4f} m/s'
            f' ({len(lost[m])} damages with one)'
        )
    return 0


def _screened(screen: TipScreen, speeds: np.ndarray, gaits: int) -> list[int]:
    """
    Return the positions within the guard, fastest first, walked until ``gaits`` of them.

    Also until one lies within the widest margin (at most :data:`SEARCH` walked).
    """
    widest = screen.guard - math.radians(max(MARGINS_DEG))
    passed = []
    for position in map(int, np.argsort(-speeds, kind='stable')[:SEARCH]):
        if not screen.tips(position):
            passed.append(position)
        if len(passed) >= gaits and min(screen.tilts[p] for p in passed) <= widest:
            break
    return passed


if __name__ == '__main__':
    raise SystemExit(main())
