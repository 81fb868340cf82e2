# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``run_navigation``: the navigation experiment (docs/navigation.md) on a repertoire.

    ros2 run hexapod_adapt run_navigation --out-dir docs/navigation [--goal-seed 0]

Every orientation of the damage scenarios (S0-S4) x ``--goals`` seeded goals at 1-3 m x three
methods: the repertoire with the learned correction, without it, and the firmware-style control
tripod steered every cycle. Prints the success rate, median walking time and path efficiency per
scenario and method; ``--out-dir`` writes runs.csv, paths.json, summary.json, paths.png (top
views) and boxes.png.
"""

from __future__ import annotations

import argparse
from dataclasses import asdict, replace
import sys

from hexapod_adapt import ArchiveError, load_archive
from hexapod_navigation.core.config import NavigationConfig
from hexapod_navigation.core.loading import load_navigation
from hexapod_navigation.core.repertoire import Repertoire, shipped_repertoire
from hexapod_navigation.core.specialists import shipped_specialists
from hexapod_navigation.core.step_bank import load_step_bank, shipped_step_bank
from hexapod_navigation.offline.experiment import (
    METHODS,
    NavigationSettings,
    run_navigation,
    summarise,
    write_results,
)
from hexapod_navigation.offline.plots import plot_navigation_boxes, plot_navigation_paths
from hexapod_sim import ENGINES, SCENARIO_NAMES
from hexapod_sim.damage import EXPERIMENT_KINDS
from hexapod_util.cli import (
    add_force,
    claim_outputs,
    FORCE_HINT,
    input_file,
    number,
    output_dir,
    run_command,
)

_DEFAULT = NavigationConfig()


def build_parser() -> argparse.ArgumentParser:
    """Return the command-line options of ``run_navigation``."""
    ap = argparse.ArgumentParser(
        prog='run_navigation',
        description=__doc__.split('\n\n')[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument('--repertoire', type=input_file, default=None, help='default: the shipped one')
    ap.add_argument('--engine', choices=ENGINES, default='mujoco', help='the engine walked on')
    ap.add_argument('--scenarios', nargs='+', choices=SCENARIO_NAMES, default=list(SCENARIO_NAMES))
    ap.add_argument('--methods', nargs='+', choices=METHODS, default=list(METHODS))
    ap.add_argument('--goals', type=number(int, 1, 1000), default=10, help='goals per damage case')
    ap.add_argument(
        '--goal-seed', type=number(int, 0, 2**32 - 1), default=0, help='seed of the goals'
    )
    ap.add_argument(
        '--tolerance', type=number(float, 0, 10, low_open=True), default=_DEFAULT.tolerance
    )
    ap.add_argument(
        '--time-limit', type=number(float, 0, 3600, low_open=True), default=_DEFAULT.time_limit
    )
    ap.add_argument(
        '--length-scale', type=number(float, 0, 10, low_open=True), default=_DEFAULT.length_scale
    )
    ap.add_argument(
        '--signal-xy', type=number(float, 0, 10, low_open=True), default=_DEFAULT.signal_std_xy
    )
    ap.add_argument(
        '--noise-xy', type=number(float, 0, 10, low_open=True), default=_DEFAULT.noise_std_xy
    )
    ap.add_argument(
        '--bank',
        choices=('default', 'on', 'off', 'leave-out'),
        default='default',
        help="the damage bank of the repertoire's steps (hexapod_navigation.core.step_bank): as"
        " NavigationConfig's use_bank says, on, off, or on with each case's own damage left out",
    )
    ap.add_argument(
        '--bank-file',
        type=input_file,
        default=None,
        help="the bank (default: the shipped repertoire's, maps/navigation_bank.npz)",
    )
    ap.add_argument(
        '--specialists',
        choices=('default', 'on', 'off'),
        default='default',
        help="gaits made for the bank's damages as more steps (hexapod_navigation.core"
        '.specialists):'
        " as NavigationConfig's specialists says, on or off (they need the bank)",
    )
    ap.add_argument(
        '--specialists-file',
        type=input_file,
        default=None,
        help='the specialists (default: the shipped ones, maps/navigation_specialists.npz)',
    )
    ap.add_argument(
        '--damage-kind',
        choices=EXPERIMENT_KINDS,
        default='lifted',
        help="how the scenarios' legs fail: lifted as in the thesis, a dead coxa, femur or tibia"
        ' servo (unpowered_*), locked where they stood, weak servos, a lost or a shortened tibia'
        ' (the shipped bank holds lifted, locked and unpowered_femur)',
    )
    ap.add_argument(
        '--reported',
        action='store_true',
        help="navigate is told each case's damage, as the robot's servo reports tell it"
        ' (favoured where the bank models it: the prior_reported setting)',
    )
    ap.add_argument('--workers', type=number(int, 1, 256), default=2)
    ap.add_argument(
        '--out-dir', type=output_dir, default=None, help='write results and plots here'
    )
    add_force(ap)
    return ap


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``run_navigation``; exit status 2 for bad inputs."""
    args = build_parser().parse_args(argv)
    # the engines' compiled modules load before the signal handlers, as part of start-up: a
    # signal inside a compiled module's import surfaces as a bare ImportError
    import hexapod_sim.physics.mujoco_engine  # noqa: F401
    import hexapod_sim.physics.pybullet_engine  # noqa: F401

    return run_command('run_navigation', lambda: _run(args))


#: What --out-dir receives.
OUT_DIR_FILES = ('runs.csv', 'paths.json', 'summary.json', 'paths.png', 'boxes.png')


def _run(args: argparse.Namespace) -> int:
    if args.out_dir is not None:  # claimed before the episodes: a refusal costs nothing
        claim_outputs([args.out_dir / name for name in OUT_DIR_FILES], args.force, FORCE_HINT)
    path = args.repertoire or shipped_repertoire()
    try:
        archive = load_archive(path)
        repertoire = Repertoire.from_archive(archive)
    except ArchiveError as exc:
        print(f'run_navigation: {exc}', file=sys.stderr)
        return 2
    config = NavigationConfig(
        **{
            **asdict(_DEFAULT),
            'tolerance': args.tolerance,
            'time_limit': args.time_limit,
            'length_scale': args.length_scale,
            'signal_std_xy': args.signal_xy,
            'noise_std_xy': args.noise_xy,
            **({} if args.bank == 'default' else {'use_bank': args.bank != 'off'}),
            **({} if args.specialists == 'default' else {'specialists': args.specialists == 'on'}),
        }
    )
    bank = args.bank_file or shipped_step_bank()
    if config.use_bank:  # a bank describes the repertoire on the engine that made it
        _, problem = load_step_bank(bank, repertoire, repertoire.engine)
        if problem and args.bank != 'default':
            print(f'run_navigation: the damage bank cannot be used: {problem}', file=sys.stderr)
            return 2
        if problem:  # as navigate_node does: learn without it, and say so
            print(f'run_navigation: no damage bank, the GP learns alone: {problem}', flush=True)
            config = replace(config, use_bank=False)
    specialists = args.specialists_file or shipped_specialists()
    if config.specialists:
        data = load_navigation(path, bank, specialists, config.specialist_max_tilt)
        problem = data.no_bank or data.no_specialists
        if problem and args.specialists == 'on':
            print(f'run_navigation: the specialists cannot be used: {problem}', file=sys.stderr)
            return 2
        if problem:
            print(f'run_navigation: no specialists: {problem}', flush=True)
            config = replace(config, specialists=False)
    settings = NavigationSettings(
        repertoire=path,
        engine=args.engine,
        scenarios=tuple(args.scenarios),
        goals=args.goals,
        goal_seed=args.goal_seed,
        methods=tuple(args.methods),
        config=config,
        bank=bank,
        leave_out=args.bank == 'leave-out',
        damage_kind=args.damage_kind,
        reported=args.reported,
        specialists=specialists,
    )
    rows, paths = run_navigation(settings, workers=args.workers)
    print('scenario  method        goals  reached  median walking s  median efficiency')
    for s in summarise(rows):
        print(
            f'{s.scenario:8s}  {s.method:12s}  {s.episodes:5d}  {100 * s.success_rate:6.1f} %'
            f'  {s.median_walking_time:16.1f}  {s.median_efficiency:17.2f}'
        )
    if args.out_dir is not None:
        write_results(args.out_dir, settings, rows, paths)
        plot_navigation_paths(rows, paths, args.out_dir / 'paths.png')
        plot_navigation_boxes(rows, args.out_dir / 'boxes.png')
        print(f'wrote {args.out_dir}/runs.csv, paths.json, summary.json, paths.png, boxes.png')
    return 0


if __name__ == '__main__':
    sys.exit(main())
