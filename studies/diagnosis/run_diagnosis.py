# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Blind adaptation that names its damage (issue 67): the experiment's runs, with a diagnosis.

Every orientation of the scenarios, damage of one kind, the default profile with the damaged
tripod as the success floor and adapt_node's tip guard, no servo report, no damage told. The
hypotheses are the shipped bank of that kind (the default map re-scored under each of its 21 leg
sets, on MuJoCo), or of every kind (``--hypotheses every``: 168); trials on ``--engine`` at its
converged step (on MuJoCo too: not the physics the hypotheses are walked in). One CSV row per
run and a summary (``BENCH``-like lines, not benchmarks):

    python -m studies.diagnosis.run_diagnosis --engine pybullet --kind lifted \
        --out studies/diagnosis/results/lifted_pybullet.csv
"""

from __future__ import annotations

import argparse
import csv
from dataclasses import asdict, replace
import math
from pathlib import Path
import sys

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_ceilings, shipped_map
from hexapod_adapt.mapping.simulation import engine_of_map
from hexapod_adapt.online.adaptation import DEFAULT_TIP_GUARD
from hexapod_adapt.online.bank import load_bank, load_diagnosis_banks, RESCORE_WHEN_NAMED
from hexapod_adapt.online.diagnosis import Weighing
from hexapod_adapt.online.experiment import ExperimentSetup, run_experiment
from hexapod_adapt.online.mboa import PROFILES, TRIAL_BUDGET
from hexapod_adapt.online.safety import RISK_LIMIT
from hexapod_adapt.online.session import (
    BlindRules,
    FirstGait,
    KIN_TILTS,
    NAME_LEG_SETS,
    SCREEN_MARGIN,
)
from hexapod_sim import SimConfig
from hexapod_sim.damage import Damage
from hexapod_sim.scenarios import scenario
import numpy as np
from studies.diagnosis.calibration import variant_physics


def fit_floor(value: str) -> float | None:
    """Parse a fit floor option: a number, or 'off' (None: no floor)."""
    return None if value == 'off' else float(value)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--engine', default='pybullet')
    parser.add_argument(
        '--variant',
        default=None,
        help="MuJoCo only: the trials' physics changed (fF: foot friction F; sS: servo"
        ' compliance slope S), a tuning set of physics the hypotheses were not walked in',
    )
    parser.add_argument('--kind', default='lifted')
    parser.add_argument('--scenarios', nargs='+', default=['S1', 'S2', 'S3', 'S4'])
    parser.add_argument('--archive', default=str(shipped_map(DEFAULT_MAP)))
    parser.add_argument(
        '--ceilings',
        default=None,
        help="the folder of the map's cached ceilings the banks are read from (default: the"
        ' shipped ones; an empty folder: a map with none cached)',
    )
    parser.add_argument('--out', required=True)
    parser.add_argument('--force', action='store_true', help='replace an existing --out file')
    parser.add_argument(
        '--leave-out',
        action='store_true',
        help="drop each run's own damage from the hypotheses: a damage no hypothesis holds",
    )
    parser.add_argument(
        '--risk-limit',
        type=float,
        default=RISK_LIMIT,
        help="the safety model's risk limit (issue 67, 2); 0: no safety model",
    )
    parser.add_argument(
        '--offset-std',
        type=float,
        default=BlindRules().offset_std,
        help="while no damage is named: M-BOA's shared speed shift [m/s] (issue 67, 3)",
    )
    parser.add_argument(
        '--stop',
        choices=('alpha', 'gain'),
        default='alpha' if BlindRules().alpha_stop else 'gain',
        help="while no damage is named: stop on alpha alone, or also on the profile's stop_gain",
    )
    parser.add_argument(
        '--temperature',
        type=float,
        default=Weighing().temperature,
        help="each trial's likelihood raised to it (issue 67, 1)",
    )
    parser.add_argument(
        '--none-deviation',
        type=float,
        default=Weighing().none_deviation,
        help='"none of these" explains a trial this many noise scales off',
    )
    parser.add_argument(
        '--bank-prior',
        action=argparse.BooleanOptionalAction,
        default=BlindRules().bank_prior,
        help="while no damage is named: M-BOA's prior is the bank weighed by the posterior",
    )
    parser.add_argument(
        '--first',
        choices=[f.value for f in FirstGait],
        default=BlindRules().first.value,
        help="while no damage is named, the first gait: the map's fastest, or the fastest on"
        ' average over the hypotheses',
    )
    parser.add_argument(
        '--unfit-fallback',
        action=argparse.BooleanOptionalAction,
        default=BlindRules().unfit_fallback,
        help='once the leader fits no trial, adapt and stop as blind M-BOA without a diagnosis',
    )
    parser.add_argument(
        '--fallback-stop',
        choices=('gain', 'alpha'),
        default='alpha' if BlindRules().fallback_alpha_stop else 'gain',
        help='a run fallen back stops as blind M-BOA does (alpha and the expected gain), or on'
        ' alpha alone',
    )
    parser.add_argument(
        '--hypotheses',
        choices=('kind', 'every', 'lifted', 'lifted-then-every'),
        default='kind',
        help="the bank: the run's kind's 21 damages, every kind's (168), the 21 lifted-leg"
        " damages whatever the run's kind (adapt_node's bank), or those and then every kind's"
        ' once no lifted leg fits',
    )
    parser.add_argument(
        '--fit-floor',
        type=fit_floor,
        default=Weighing().fit_floor,
        help='name a hypothesis only when its mean log likelihood over the trials is at least'
        " this ('off': no floor)",
    )
    parser.add_argument(
        '--wider-fit-floor',
        type=fit_floor,
        default=Weighing().wider_fit_floor,
        help="the fit floor once the run widens its bank (--hypotheses lifted-then-every; 'off':"
        ' no floor)',
    )
    parser.add_argument(
        '--rescore-when-named',
        action=argparse.BooleanOptionalAction,
        default=RESCORE_WHEN_NAMED,
        help='the wider bank (--hypotheses lifted-then-every) weighs its damages not cached too,'
        ' each re-scored when a run names it',
    )
    parser.add_argument(
        '--leg-sets',
        action=argparse.BooleanOptionalAction,
        default=NAME_LEG_SETS,
        help='name a leg set when its hypotheses of several kinds hold the threshold together',
    )
    parser.add_argument(
        '--screen-margin',
        type=float,
        default=math.degrees(SCREEN_MARGIN),
        help="[deg] a named damage's tip screen vetoes tilts past the tip guard less this",
    )
    parser.add_argument(
        '--kin-tilts',
        type=float,
        default=KIN_TILTS,
        help="while the lifted bank is weighed, the safety model's tilt of a leg set believed at"
        ' least this much is the worst of the kinds that unload those legs (0: every one in play)',
    )
    parser.add_argument(
        '--no-kin-tilts',
        dest='kin_tilts',
        action='store_const',
        const=None,
        help='each lifted hypothesis tilts as its own walk (the safety model before 2026-12-07)',
    )
    parser.add_argument(
        '--calibrate',
        type=int,
        default=0,
        help="walk the map's this many fastest gaits intact on the trials' physics first, and"
        ' weigh the trials against the gap they measure (0: none)',
    )
    parser.add_argument(
        '--workers',
        type=int,
        default=1,
        help='processes that walk the hypotheses (the same walks and runs, sooner)',
    )
    args = parser.parse_args(argv)
    if args.workers < 1:
        parser.error('--workers takes 1 or more')
    if args.calibrate == 1 or args.calibrate < 0:
        parser.error('--calibrate takes 0 (none) or two gaits or more')
    blind = BlindRules(
        args.offset_std,
        args.stop == 'alpha',
        args.bank_prior,
        FirstGait(args.first),
        args.unfit_fallback,
        args.fallback_stop == 'alpha',
    )
    weighing = Weighing(
        args.none_deviation,
        temperature=args.temperature,
        fit_floor=args.fit_floor,
        wider_fit_floor=args.wider_fit_floor,
    )
    if args.variant is not None and args.engine != 'mujoco':
        parser.error('--variant changes MuJoCo trials only')
    if '+' in args.kind and args.hypotheses == 'kind':
        parser.error(f'--kind {args.kind} is two kinds at once: no bank of it; --hypotheses?')
    trials = (
        SimConfig.converged(args.engine) if args.variant is None else variant_physics(args.variant)
    )
    archive = load_archive(args.archive)
    map_engine = engine_of_map(archive)
    cache = shipped_ceilings() if args.ceilings is None else Path(args.ceilings)
    legs_all = [legs for name in ('S1', 'S2', 'S3', 'S4') for legs in scenario(name)]
    if args.hypotheses == 'kind':
        own = [Damage.of(args.kind, legs) for legs in legs_all]
        bank, wider = load_bank(archive, map_engine, [cache], own), None
    else:
        bank, wider = load_diagnosis_banks(
            archive, map_engine, [cache], args.hypotheses, args.rescore_when_named
        )
    for which, b in (('bank', bank), ('wider bank', wider)):
        if b is not None:
            print(f'{which}: {b.describe()}', file=sys.stderr)
    setup = ExperimentSetup(
        scenarios=tuple(args.scenarios),
        config=replace(PROFILES['default'], max_trials=TRIAL_BUDGET),
        # the converged step on every engine: on MuJoCo too, a physics the hypotheses (walked at
        # the map's step) were not walked in
        trial_config=trials,
        floor=True,
        setup='default+diagnosis'
        + (f'+safety{args.risk_limit:g}' if args.risk_limit else '')
        + f'+{args.stop}stop+offset{args.offset_std:g}'
        + f'+t{args.temperature:g}+none{args.none_deviation:g}'
        + ('' if args.fit_floor is None else f'+fit{args.fit_floor:g}')
        + (
            ''
            if args.wider_fit_floor == args.fit_floor or args.hypotheses != 'lifted-then-every'
            else '+widerfit'
            + ('off' if args.wider_fit_floor is None else f'{args.wider_fit_floor:g}')
        )
        + ('+bankprior' if args.bank_prior else '')
        + ('' if args.unfit_fallback else '+no-unfit-fallback')
        + ('+fallback-alpha-stop' if args.unfit_fallback and args.fallback_stop == 'alpha' else '')
        + ('' if args.first == FirstGait.FASTEST.value else f'+first-{args.first}')
        + {
            'every': '+every-kind',
            'lifted': '+lifted-bank',
            'lifted-then-every': '+lifted-then-every',
            'kind': '',
        }[args.hypotheses]
        + ('+leg-sets' if args.leg_sets and 'every' in args.hypotheses else '')
        + ('+rescore-named' if args.rescore_when_named and wider is not None else '')
        + ('' if args.variant is None else f'+trials-{args.variant}')
        + ('' if args.ceilings is None else '+other-ceilings')
        + (f'+margin{args.screen_margin:g}' if args.screen_margin else '')
        + (f'+calibrate{args.calibrate}' if args.calibrate else '')
        + (
            ''
            if args.kin_tilts == KIN_TILTS  # the default's runs are labelled as before it
            else '+no-kin'
            if args.kin_tilts is None
            else f'+kin{args.kin_tilts:g}'
        ),
        bank=bank,
        leave_out=args.leave_out,
        kind=args.kind,
        tip_guard=DEFAULT_TIP_GUARD,
        diagnose=True,
        walk_workers=args.workers,
        safety=args.risk_limit or None,
        blind=blind,
        weighing=weighing,
        leg_sets=args.leg_sets,
        screen_margin=math.radians(args.screen_margin),
        wider=wider,
        calibrate=args.calibrate,
        kin_tilts=args.kin_tilts,
    )
    out = Path(args.out)
    if out.exists() and not args.force:
        print(f'{out} exists: --force replaces it', file=sys.stderr)
        return 2
    out.parent.mkdir(parents=True, exist_ok=True)
    rows = []
    with open(out, 'w', newline='', encoding='utf-8') as f:
        writer = None

        def on_row(row) -> None:
            nonlocal writer
            data = asdict(row)
            if writer is None:
                writer = csv.DictWriter(f, fieldnames=list(data))
                writer.writeheader()
            writer.writerow(data)
            f.flush()
            rows.append(row)
            named = row.named.split('|')
            print(
                f'{row.scenario} legs {row.failed_legs}: {row.trials} trials, best'
                f' {row.best_speed:.3f} m/s (tripod {row.control_speed:.3f}), tipped'
                f' {row.tipped_trials}, vetoed {row.vetoed}, {row.hypothesis_walks} walks; named'
                f' {named[:3]}; {row.posterior}',
                flush=True,
            )

        run_experiment(archive, setup, on_row)
    summarise(rows, args.kind, args.engine)
    return 0


def summarise(rows, kind: str, engine: str) -> None:
    """Print the figures issue 67's acceptance names, for these runs."""
    tag = f'{kind}_{engine}'
    for k in (2, 3):
        correct = sum(r.named_after(k) == Damage.of(kind, r.failed_legs).label for r in rows)
        print(f'diagnosis_correct_after_{k}_{tag} {correct} of {len(rows)}')
        legs = sum(r.legs_named_after(k) == tuple(r.failed_legs) for r in rows)
        print(f'legs_named_after_{k}_{tag} {legs} of {len(rows)}')
    print(f'trials_median_{tag} {np.median([r.trials for r in rows]):g}')
    print(f'best_mean_{tag} {np.mean([r.best_speed for r in rows]):.3f} m/s')
    print(f'tipped_trials_{tag} {sum(r.tipped_trials for r in rows)}')
    print(f'no_hypothesis_fits_{tag} {sum(r.unfit for r in rows)} of {len(rows)}')
    print(f'widened_{tag} {sum(r.widened > 0 for r in rows)} of {len(rows)}')
    print(f'vetoed_{tag} {sum(r.vetoed for r in rows)}')
    walks = [r.hypothesis_walks for r in rows]
    first, median = walks[0], np.median(walks)
    print(f'hypothesis_walks_{tag} {sum(walks)} (first run {first}, median {median:g})')
    print(f'beat_tripod_{tag} {sum(r.best_speed > r.control_speed for r in rows)} of {len(rows)}')
    for k in (1, 3, 5, 8, 12, 24):
        print(f'best_after_{k}_{tag} {np.mean([r.best_after(k) for r in rows]):.3f} m/s')


if __name__ == '__main__':
    raise SystemExit(main())
