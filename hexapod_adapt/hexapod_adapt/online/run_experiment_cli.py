# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``run_experiment``: the thesis's simulated adaptation experiment (5.2) on one map.

    ros2 run hexapod_adapt run_experiment [--archive map.npz] [--scenarios S1 S3] [--out runs.csv]
    run_experiment --ceilings hexapod_adapt/maps/ceilings --out-dir docs/experiment  # docs picture

For every orientation of each failure scenario: one M-BOA run with simulated trials (leg
failures as in table 5.1, collisions not fatal), next to the control tripod gait with the same
damage and intact. Trials run on the engine that made the map, or ``--trial-engine``;
``--cross-engine`` runs the whole experiment on the map's engine and again on each other one,
the judge (DART) included (a stand-in for the reality gap of thesis 5.5). ``--damage-kind``
gives the scenarios' legs another damage than the thesis's lifted one (e.g.
``unpowered_femur``: a dead femur servo).
Prints a row per run and a summary per scenario
and engine; ``--out`` writes the rows as CSV (atomically); ``--out-dir`` writes runs.csv plus
the box plots adapted_speed.png and trials.png (thesis figs 5.4-5.5).
"""

from __future__ import annotations

import argparse
import csv
from dataclasses import asdict, replace
import io
import sys

from hexapod_adapt.mapping.archive import ArchiveError, load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_ceilings, shipped_map
from hexapod_adapt.mapping.simulation import engine_of_map
from hexapod_adapt.online.adaptation import DEFAULT_TIP_GUARD
from hexapod_adapt.online.bank import load_bank
from hexapod_adapt.online.ceiling import ceiling
from hexapod_adapt.online.experiment import (
    EXPERIMENT_MAX_TRIALS,
    ExperimentRow,
    ExperimentSetup,
    run_experiment,
)
from hexapod_adapt.online.experiment_plots import plot_experiment
from hexapod_adapt.online.mboa import (
    ALPHA_RANGE,
    DEFAULT_PROFILE,
    KAPPA_RANGE,
    LENGTH_SCALE_RANGE,
    MAX_TRIALS_LIMIT,
    MboaConfig,
    NOISE_RANGE,
    PROFILES,
    STOP_GAIN_RANGE,
    TRIAL_BUDGET,
    TRIAL_SETTLE,
)
from hexapod_adapt.online.run_config import PROFILE_SETTINGS
from hexapod_sim import ENGINES
from hexapod_sim.damage import check_experiment_kind, Damage, EXPERIMENT_KINDS
from hexapod_sim.scenarios import scenario
from hexapod_util.cli import (
    acknowledge_stop,
    add_force,
    claim_outputs,
    FORCE_HINT,
    input_file,
    number,
    output_dir,
    output_file,
    run_command,
)
from hexapod_util.files import atomic_write_bytes
import numpy as np

SCENARIOS = ('S1', 'S2', 'S3', 'S4')


def rows_csv(rows: list[ExperimentRow]) -> bytes:
    """Return the rows as CSV text (failed legs space-separated)."""
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=list(asdict(rows[0])))
    writer.writeheader()
    for r in rows:
        d = asdict(r)
        d['failed_legs'] = ' '.join(map(str, r.failed_legs))
        writer.writerow(d)
    return buf.getvalue().encode()


def summary(rows: list[ExperimentRow]) -> str:
    """
    Summarise the runs per trial engine and scenario.

    Runs, trials (median / max), adapted speed (median / mean), runs beating the damaged control
    tripod, the control speeds.
    """
    lines = [
        'trials on  scenario  runs  trials med/max  adapted med/mean m/s  beat control  control'
        ' m/s  intact m/s  adapted/ceiling med/min'
    ]
    for engine in dict.fromkeys(r.trial_engine for r in rows):
        for name in dict.fromkeys(r.scenario for r in rows):
            sel = [r for r in rows if r.scenario == name and r.trial_engine == engine]
            if not sel:
                continue
            best = np.array([r.best_speed for r in sel])
            control = np.array([r.control_speed for r in sel])
            lines.append(
                f'{engine:9s} {name:8s}  {len(sel):4d}  {np.median([r.trials for r in sel]):6.1f}'
                f' / {max(r.trials for r in sel):3d}      {np.median(best):+.3f} /'
                f' {np.mean(best):+.3f}      {int(np.sum(best > control)):3d} of {len(sel):2d}   '
                f' {np.mean(control):+.3f}       {sel[0].intact_control_speed:+.3f}'
                + (
                    f'      {np.median([r.ratio for r in sel]):.2f} /'
                    f' {min(r.ratio for r in sel):.2f}'
                    if all(r.ceiling_niche >= 0 for r in sel)
                    else ''
                )
            )
    return '\n'.join(lines)


def _kind_arg(text: str) -> str:
    try:
        return check_experiment_kind(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def build_parser() -> argparse.ArgumentParser:
    """Return the command-line options of ``run_experiment``."""
    ap = argparse.ArgumentParser(
        prog='run_experiment',
        description=__doc__.split('\n\n')[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    _run_options(ap)
    _mboa_options(ap)
    _trial_options(ap)
    _prior_and_outputs(ap)
    add_force(ap)
    return ap


def _run_options(ap: argparse.ArgumentParser) -> None:
    """Add the map, the scenarios, the damage and the engines."""
    ap.add_argument(
        '--archive',
        type=input_file,
        default=None,
        help='the map (.npz; default: the shipped default map)',
    )
    ap.add_argument(
        '--scenarios',
        nargs='+',
        default=list(SCENARIOS),
        choices=SCENARIOS,
        help='failure scenarios to run (every orientation of each)',
    )
    ap.add_argument(
        '--damage-kind',
        type=_kind_arg,
        default='lifted',
        help="what each scenario's failed legs suffer: the thesis's lifted legs (default), a dead"
        ' coxa, femur or tibia servo (unpowered_*: the joint free, the leg folded by the live'
        ' ones), locked, weak, a lost or a shortened tibia (hexapod_sim.damage), weak and'
        ' shortened with an amount as shortened:0.25; two kinds at once as A+B, for two-leg'
        ' scenarios (S2-S4): ' + ', '.join(EXPERIMENT_KINDS),
    )
    ap.add_argument(
        '--trial-engine',
        choices=ENGINES,
        default=None,
        help='engine the trials run on (default: the engine that made the map)',
    )
    ap.add_argument(
        '--cross-engine',
        action='store_true',
        help="run on the map's engine and again on each other engine (the judge included), each"
        " other engine at its converged step, as make bench-adapt's _cross and _judge runs",
    )


def _mboa_options(ap: argparse.ArgumentParser) -> None:
    """Add M-BOA's settings (each the profile's unless given)."""
    ap.add_argument(
        '--max-trials',
        type=number(int, 1, MAX_TRIALS_LIMIT),
        default=None,
        help=f'trials per run at most (default: {TRIAL_BUDGET}, the budget users get; with'
        f' --profile thesis {EXPERIMENT_MAX_TRIALS}, a cap, so that the thesis rule ends the'
        ' runs)',
    )
    ap.add_argument(
        '--profile',
        choices=sorted(PROFILES),
        default=DEFAULT_PROFILE,
        help="M-BOA settings: 'default' (chosen on the tuning set) or 'thesis' (thesis 5.2.2)",
    )
    ap.add_argument(
        '--alpha', type=number(float, *ALPHA_RANGE), default=None, help="stop ratio (profile's)"
    )
    ap.add_argument(
        '--kappa',
        type=number(float, *KAPPA_RANGE),
        default=None,
        help="UCB weight on the posterior std (profile's)",
    )
    ap.add_argument(
        '--length-scale',
        type=number(float, *LENGTH_SCALE_RANGE),
        default=None,
        help="Matern length scale rho (profile's)",
    )
    ap.add_argument(
        '--noise',
        type=number(float, *NOISE_RANGE),
        default=None,
        help="GP noise variance [(m/s)^2] (profile's)",
    )
    ap.add_argument(
        '--stop-gain',
        type=number(float, *STOP_GAIN_RANGE),
        default=None,
        help="blind runs: success also needs the next trial's expected gain below this [m/s]"
        " (profile's)",
    )
    ap.add_argument(
        '--no-gain-stop',
        action='store_true',
        help='no expected-gain stop: runs end on alpha or the budget alone',
    )


def _trial_options(ap: argparse.ArgumentParser) -> None:
    """Add the success floor and the trials' timing."""
    ap.add_argument(
        '--floor',
        action=argparse.BooleanOptionalAction,
        default=None,
        help='the damaged control tripod, measured first, is the success floor (default: on,'
        ' off for the thesis profile)',
    )
    ap.add_argument(
        '--trial-duration',
        type=number(float, 0.1, 120.0),
        default=None,
        help="timed seconds per trial (default: the map's, 5 s)",
    )
    ap.add_argument(
        '--settle',
        type=number(float, 0.0, 60.0),
        default=TRIAL_SETTLE,
        help='untimed walking before each trial is timed [s] (default 0: timed from standing,'
        " the thesis's trial and the product's)",
    )


def _prior_and_outputs(ap: argparse.ArgumentParser) -> None:
    """Add the prior, the bank, the ceilings and the outputs."""
    ap.add_argument(
        '--prior',
        choices=('map', 'damage'),
        default='map',
        help="'damage': M-BOA starts from the map re-scored under each run's damage on the map's"
        ' engine (a damage-informed prior; needs --ceilings)',
    )
    ap.add_argument(
        '--bank',
        choices=('profile', 'off', 'on', 'leave-out'),
        default='profile',
        help='damage hypotheses (hexapod_adapt.online.bank, read from the shipped ceilings and'
        ' --ceilings) for runs without --prior damage: as the profile says (none uses them:'
        " studies/adaptation/README.md), 'off', 'on', or 'leave-out': each run's own damage left"
        ' out of them',
    )
    ap.add_argument(
        '--ceilings',
        type=output_dir,
        default=None,
        help="cache of the map's ceilings (every gait under each damage, on the trials' engine"
        ' and step; computed if missing: about 15 core-minutes a case for the default map on'
        ' MuJoCo, its own engine, and several times that on an engine at its converged step):'
        " adds each run's ceiling and adapted/ceiling ratio",
    )
    ap.add_argument(
        '--workers', type=number(int, 1, 256), default=1, help='processes for missing ceilings'
    )
    ap.add_argument('--out', type=output_file, help='CSV file of the runs')
    ap.add_argument(
        '--out-dir',
        type=output_dir,
        help='directory for runs.csv, adapted_speed.png and trials.png',
    )


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``run_experiment``; exit status 2 for bad inputs."""
    args = build_parser().parse_args(argv)
    return run_command('run_experiment', lambda: _experiment(args))


#: What --out-dir receives.
OUT_DIR_FILES = ('runs.csv', 'adapted_speed.png', 'trials.png', 'ceiling_ratio.png')


def _config(args: argparse.Namespace) -> MboaConfig:
    """Return M-BOA's settings: the profile's, with what the options give; ValueError if bad."""
    chosen = {
        name: getattr(args, name) for name in PROFILE_SETTINGS if getattr(args, name) is not None
    }
    if args.no_gain_stop:
        chosen['stop_gain'] = None
    budget = args.max_trials or (
        EXPERIMENT_MAX_TRIALS if args.profile == 'thesis' else TRIAL_BUDGET
    )
    config = replace(PROFILES[args.profile], max_trials=budget, **chosen)
    if args.bank != 'profile':
        config = replace(config, use_bank=args.bank in ('on', 'leave-out'))
    if args.prior == 'damage' and args.ceilings is None:
        raise ValueError('--prior damage needs --ceilings (where the re-scored maps are)')
    return config


def _setup_name(args: argparse.Namespace) -> str:
    """Return the rows' name of the setup: the profile, and what the options add to it."""
    uses_bank = PROFILES[args.profile].use_bank
    if args.prior == 'damage':
        suffix = '+prior'
    elif args.bank == 'leave-out':
        suffix = '+bank-leave-out'
    elif args.bank == 'on' and not uses_bank:
        suffix = '+bank'
    elif args.bank == 'off' and uses_bank:
        suffix = '-bank'
    else:
        suffix = ''
    return args.profile + suffix


def _show(r: ExperimentRow) -> None:
    print(
        f'{r.trial_engine:8s} {r.scenario} legs {",".join(map(str, r.failed_legs)):4s}'
        f' {r.damage_kind}'
        f' {r.trials:3d} trials  adapted {r.best_speed:+.3f} m/s  control'
        f' {r.control_speed:+.3f} m/s'
        + (
            f'  ceiling {r.ceiling_speed:.3f} m/s, ratio {r.ratio:.2f}'
            if r.ceiling_niche >= 0
            else ''
        ),
        flush=True,
    )


def _experiment(args: argparse.Namespace) -> int:
    # the outputs are claimed before the runs: a refusal costs nothing
    outputs = [args.out] if args.out else []
    outputs += [args.out_dir / name for name in OUT_DIR_FILES] if args.out_dir else []
    claim_outputs(outputs, args.force, FORCE_HINT)
    try:
        archive = load_archive(args.archive or shipped_map(DEFAULT_MAP))
        config = _config(args)
        for name in args.scenarios:  # two kinds at once need two legs: refused before any run
            Damage.of(args.damage_kind, scenario(name)[0])
    except (ArchiveError, ValueError) as exc:
        print(f'run_experiment: {exc}', file=sys.stderr)
        return 2
    map_engine = engine_of_map(archive)
    first = args.trial_engine or map_engine
    engines = [first] + ([e for e in ENGINES if e != first] if args.cross_engine else [])

    def ceilings(damage, engine):
        return ceiling(archive, damage, engine, args.ceilings, args.workers)

    def priors(damage):  # the map re-scored under the damage on the map's own engine
        return ceilings(damage, map_engine).speeds

    bank = None
    if config.use_bank and args.prior != 'damage':
        dirs = [shipped_ceilings()] + ([args.ceilings] if args.ceilings else [])
        bank = load_bank(archive, map_engine, dirs)
        print(f'damage bank: {bank.describe()}', flush=True)
    setup = ExperimentSetup(
        args.scenarios,
        config,
        ceilings=ceilings if args.ceilings is not None else None,
        floor=args.floor if args.floor is not None else args.profile != 'thesis',
        priors=priors if args.prior == 'damage' else None,
        setup=_setup_name(args),
        trial_duration=args.trial_duration,
        settle=args.settle,
        bank=bank,
        leave_out=args.bank == 'leave-out',
        kind=args.damage_kind,
        tip_guard=DEFAULT_TIP_GUARD,  # adapt_node's
    )
    rows: list[ExperimentRow] = []
    try:
        for engine in engines:
            rows += run_experiment(archive, replace(setup, trial_engine=engine), on_row=_show)
    except KeyboardInterrupt:  # Ctrl-C or SIGTERM: the completed runs are kept
        acknowledge_stop()
        if rows:
            _write_csv(args, rows)
        raise
    print()
    print(summary(rows))
    _write_csv(args, rows)
    if args.out_dir:
        names = ('adapted_speed.png', 'trials.png', 'ceiling_ratio.png')
        for path in plot_experiment(rows, *(args.out_dir / name for name in names)):
            print(f'wrote {path}')
    return 0


def _write_csv(args: argparse.Namespace, rows: list[ExperimentRow]) -> None:
    """Write the runs to --out and to --out-dir/runs.csv, if asked for."""
    for path in (args.out, args.out_dir / 'runs.csv' if args.out_dir else None):
        if path is not None:
            atomic_write_bytes(path, rows_csv(rows))
            print(f'wrote {path} ({len(rows)} runs)', flush=True)


if __name__ == '__main__':
    sys.exit(main())
