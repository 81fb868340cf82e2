# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
r"""
The damage-informed prior on physics the map does not know: a speed shift all gaits share.

A run that knows its damage starts from the map re-scored under it on the map's engine and
stops on alpha alone: once its best trial walks at least alpha times the best the GP still
expects. Where every gait walks slower than the re-score says (another engine, the robot), one
trial lowers only its neighbours' predictions, and the run walks on until the far gaits' are
lowered too. ``MboaConfig.offset_std`` is a speed shift every gait shares, learned from each
trial (blind runs use 0.05 m/s: ``BlindRules``). This runs the prior's experiment (lifted legs,
S1-S4, 21 runs, the default profile, the damaged tripod as the floor, adapt_node's tip guard)
with trials on a MuJoCo physics variant (:func:`studies.diagnosis.calibration.variant_physics`)
and a given shift.

    python -m studies.adaptation.prior_shift --variant s128 --offset-std 0.05 --out X.csv
"""

from __future__ import annotations

import argparse
import csv
from dataclasses import asdict, replace
from pathlib import Path
import sys

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_ceilings, shipped_map
from hexapod_adapt.mapping.simulation import engine_of_map
from hexapod_adapt.online.adaptation import DEFAULT_TIP_GUARD
from hexapod_adapt.online.ceiling import ceiling
from hexapod_adapt.online.experiment import ExperimentSetup, run_experiment
from hexapod_adapt.online.mboa import PROFILES, TRIAL_BUDGET
from hexapod_sim import SimConfig
from studies.adaptation.map_ab import line, summary
from studies.diagnosis.calibration import variant_physics


def main(argv: list[str] | None = None) -> int:
    """Run the prior's experiment on one physics with one shift; write its rows."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--variant', default='stock', help='MuJoCo trials: stock, fF, sS, rN')
    parser.add_argument(
        '--engine', default='mujoco', help='trials on this engine (not mujoco: no --variant)'
    )
    parser.add_argument('--offset-std', type=float, default=0.0, help='[m/s] the shared shift')
    parser.add_argument('--out', type=Path, required=True)
    parser.add_argument('--force', action='store_true', help='replace an existing --out file')
    args = parser.parse_args(argv)
    if args.out.exists() and not args.force:
        parser.error(f'{args.out} exists: --force replaces it')
    if args.engine != 'mujoco' and args.variant != 'stock':
        parser.error('--variant changes MuJoCo trials only')
    archive = load_archive(shipped_map(DEFAULT_MAP))
    map_engine = engine_of_map(archive)
    cached = shipped_ceilings()

    def priors(damage):  # the map re-scored under the damage (the shipped cache)
        return ceiling(archive, damage, map_engine, cached).speeds

    trials = (
        variant_physics(args.variant)
        if args.engine == 'mujoco'
        else SimConfig.converged(args.engine)
    )
    setup = ExperimentSetup(
        config=replace(
            PROFILES['default'], max_trials=TRIAL_BUDGET, prior_offset_std=args.offset_std
        ),
        trial_engine=args.engine,
        trial_config=trials,
        floor=True,
        priors=priors,
        setup=f'default+prior+offset{args.offset_std:g}+trials-{args.engine}-{args.variant}',
        tip_guard=DEFAULT_TIP_GUARD,
    )
    rows = run_experiment(archive, setup, on_row=lambda row: print(line(row), flush=True))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    with open(args.out, 'w', newline='', encoding='utf-8') as f:
        writer = csv.DictWriter(f, fieldnames=list(asdict(rows[0])))
        writer.writeheader()
        writer.writerows(asdict(r) for r in rows)
    print(summary(rows), flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
