# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
r"""
``generate_map``: build a behaviour-performance map offline.

Thin front end of hexapod_adapt.mapping.generate.

    ros2 run hexapod_adapt generate_map --out maps/map_s1.npz --niches 10000 \\
        --evaluations 1000000 --seed 1                         # all local cores
    generate_map ... --backend dask --scheduler tcp://head:8786  # a Dask cluster (dask-jobqueue)
    mpiexec -n 64 python -m mpi4py.futures -m hexapod_adapt.mapping.generate_map_cli ... \\
        --backend mpi
    generate_map ... --resume                                    # continue after a queue limit
    generate_map ... --force                                     # replace an existing map
    generate_map --kind navigation --out maps/navigation.npz ...  # a navigation repertoire
"""

from __future__ import annotations

import argparse
import math
import sys

from hexapod_adapt.mapping.archive import MAP_KINDS
from hexapod_adapt.mapping.emitter_settings import EMITTER_SETS
from hexapod_adapt.mapping.generate import (
    BACKENDS,
    EmptyMapError,
    generate_map,
    GenerateConfig,
    LIMITS,
)
from hexapod_adapt.mapping.robust import RobustScore, STATISTICS
from hexapod_adapt.mapping.simulation import WalkGuards
from hexapod_sim import ENGINES
from hexapod_util.cli import claim_outputs, number, output_dir, output_file, run_command
from tqdm import tqdm


def _limited(name: str):
    kind = float if isinstance(LIMITS[name][0], float) else int
    return number(kind, *LIMITS[name])


def build_parser() -> argparse.ArgumentParser:
    """Return the command-line options of ``generate_map``."""
    ap = argparse.ArgumentParser(
        prog='generate_map',
        description=__doc__.split('\n\n')[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument('--out', type=output_file, required=True, help='archive file to write (.npz)')
    _map_options(ap)
    _emitter_options(ap)
    _parallel_options(ap)
    _run_options(ap)
    _gait_guards(ap)
    return ap


def _map_options(ap: argparse.ArgumentParser) -> None:
    """Add what map to make: its kind, size, budget, seed and physics."""
    ap.add_argument(
        '--kind',
        choices=tuple(MAP_KINDS),
        default='gait',
        help=(
            'gait: the thesis map (duty-factor niches, speed); navigation: a repertoire of'
            ' omnidirectional gaits by displacement (docs/navigation.md)'
        ),
    )
    ap.add_argument(
        '--niches', type=_limited('niches'), default=10000, help='CVT niches (thesis: 40000)'
    )
    ap.add_argument(
        '--evaluations',
        type=_limited('evaluations'),
        default=1_000_000,
        help='total evaluations (thesis: 4e7)',
    )
    ap.add_argument(
        '--seed',
        type=_limited('seed'),
        default=0,
        help="seed of the CVT and of every candidate (the map's identity)",
    )
    ap.add_argument(
        '--engine',
        choices=ENGINES,
        default='mujoco',
        help=(
            'physics engine of the evaluations (mujoco: ~7x faster per core; pybullet: the'
            " thesis's)"
        ),
    )
    ap.add_argument(
        '--substeps',
        type=_limited('substeps'),
        default=0,
        help="the engine's physics steps per 240 Hz row, recorded in the map (0: its default;"
        " MuJoCo's 1 has not converged on fast gaits, docs/simulator.md)",
    )


def _emitter_options(ap: argparse.ArgumentParser) -> None:
    """Add the emitter set and pyribs' settings."""
    ap.add_argument(
        '--emitters',
        choices=EMITTER_SETS,
        default='iso_line',
        help="who proposes gaits after the random start: iso_line (the thesis's operator);"
        ' cma_me or cma_mae (pyribs improvement emitters: CMA-ES inside the archive); bandit (a'
        ' UCB1 bandit over CMA-ES, random-direction and iso+line emitters)',
    )
    ap.add_argument(
        '--emitter-count', type=_limited('emitter_count'), default=5, help='emitters per lane'
    )
    ap.add_argument(
        '--emitter-batch',
        type=_limited('emitter_batch'),
        default=36,
        help='solutions per emitter per ask',
    )
    ap.add_argument(
        '--sigma0', type=_limited('sigma0'), default=0.15, help="CMA-ES's initial step size"
    )
    ap.add_argument(
        '--lanes',
        type=_limited('lanes'),
        default=2,
        help='emitter sets asked in turn, so that no worker waits for a batch to end',
    )


def _parallel_options(ap: argparse.ArgumentParser) -> None:
    """Add where the evaluations run."""
    ap.add_argument(
        '--backend',
        choices=BACKENDS,
        default='local',
        help='local process pool, a Dask cluster, MPI, or inline in this process',
    )
    ap.add_argument(
        '--workers',
        type=_limited('workers'),
        default=0,
        help='local worker processes (0 = every core)',
    )
    ap.add_argument('--scheduler', help='Dask scheduler address (default: a local Dask cluster)')
    ap.add_argument(
        '--lag',
        type=_limited('lag'),
        default=0,
        help="candidates in flight; part of the map's identity (0 = max(64, 4 x workers))",
    )
    ap.add_argument(
        '--chunk',
        type=_limited('chunk'),
        default=0,
        help=(
            "candidates per worker call; part of the map's identity (0 = 8 for mujoco, 1 for"
            ' pybullet)'
        ),
    )


def _run_options(ap: argparse.ArgumentParser) -> None:
    """Add the CVT, checkpoints, logs, and what to do with existing files."""
    ap.add_argument(
        '--random-init',
        type=_limited('random_init'),
        default=0.01,
        help='fraction of niches filled at random first',
    )
    ap.add_argument(
        '--cvt-samples',
        type=_limited('cvt_samples'),
        default=None,
        help='K-means samples (default 25 per niche)',
    )
    ap.add_argument(
        '--cvt-dir',
        type=output_dir,
        default=None,
        help='where centroids_<n>_6.dat is cached (default: next to --out)',
    )
    ap.add_argument(
        '--checkpoint-every',
        type=number(float, 0, None, low_open=True),
        default=600.0,
        help='seconds between checkpoints',
    )
    ap.add_argument(
        '--log-every',
        type=number(float, 0, None, low_open=True),
        default=30.0,
        help='seconds between log lines',
    )
    ap.add_argument(
        '--log',
        type=output_file,
        default=None,
        help='JSON-lines progress log (default <out>.log.jsonl)',
    )
    existing = ap.add_mutually_exclusive_group()
    existing.add_argument(
        '--resume',
        action='store_true',
        help='continue from <out>.ckpt.npz if present, else a finished <out> (more --evaluations)',
    )
    existing.add_argument(
        '--force',
        action='store_true',
        help='start afresh over an existing <out>, its checkpoint and log (kept as NAME.bak)',
    )


def _gait_guards(ap: argparse.ArgumentParser) -> None:
    """Add the presets and the filters of the gaits a map may hold."""
    ap.add_argument(
        '--with-presets',
        action='store_true',
        help='try the preset gaits (control, tripod, wave, quadruped) before anything else',
    )
    ap.add_argument(
        '--min-stance-legs',
        type=int,
        default=0,
        metavar='K',
        help='navigation: only gaits that keep K feet on the ground throughout (0: any)',
    )
    ap.add_argument(
        '--min-feet',
        type=float,
        default=0.0,
        metavar='F',
        help='gait maps: only gaits with at least F feet on the ground on average (0: any)',
    )
    ap.add_argument(
        '--max-tilt',
        type=float,
        default=math.pi,
        metavar='RAD',
        help='gait maps: only gaits whose body never tilts past RAD (roll or pitch; pi: any)',
    )
    ap.add_argument(
        '--variants',
        type=int,
        default=0,
        metavar='K',
        help='gait maps on MuJoCo: walk each gait in K physics variants (friction, servos, '
        'latency, masses, floor) and store a low statistic of the K (0: the model alone)',
    )
    ap.add_argument(
        '--statistic',
        choices=sorted(STATISTICS),
        default='min',
        help='with --variants: the statistic of the K distances a map stores (default: min)',
    )
    ap.add_argument(
        '--variant-seed',
        type=int,
        default=0,
        metavar='S',
        help='with --variants: the seed the K variants are drawn from (default: 0)',
    )
    ap.add_argument('--quiet', action='store_true', help='no progress bar or progress lines')
    ap.add_argument(
        '--no-bar', action='store_true', help='progress lines instead of a progress bar (logs, CI)'
    )


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``generate_map``; exit status 1 for a failed run, 2 for bad options."""
    args = build_parser().parse_args(argv)
    return run_command(
        'generate_map',
        lambda: _generate(args),
        f'the last checkpoint is kept; continue with --resume ({args.out}.ckpt.npz)',
    )


def _config(args: argparse.Namespace) -> GenerateConfig:
    """Return the run's settings from the command line (ValueError: a setting is wrong)."""
    config = GenerateConfig(
        out=args.out,
        niches=args.niches,
        evaluations=args.evaluations,
        seed=args.seed,
        backend=args.backend,
        workers=args.workers,
        scheduler=args.scheduler,
        lag=args.lag,
        chunk=args.chunk,
        random_init=args.random_init,
        cvt_samples=args.cvt_samples,
        cvt_dir=args.cvt_dir,
        checkpoint_every=args.checkpoint_every,
        log_every=args.log_every,
        log=args.log,
        resume=args.resume,
        with_presets=args.with_presets,
        engine=args.engine,
        substeps=args.substeps,
        kind=args.kind,
        min_stance_legs=args.min_stance_legs,
        guards=WalkGuards(args.min_feet, args.max_tilt),
        robust=RobustScore(args.variants, args.statistic, args.variant_seed),
        emitters=args.emitters,
        emitter_count=args.emitter_count,
        emitter_batch=args.emitter_batch,
        sigma0=args.sigma0,
        lanes=args.lanes,
    )
    config.engine_config()
    return config


class _Progress:
    """
    Print a run's progress: a bar, one line a report (``--no-bar``) or nothing (``--quiet``).

    The bar is made at the first report, so a resumed run's rate and ETA count this run only.
    """

    def __init__(self, args: argparse.Namespace) -> None:
        self.args, self.bar = args, None

    def __call__(self, p) -> None:
        if self.args.quiet:
            return
        if self.args.no_bar:
            print(
                f'{p.evaluations:>10d} evals  {p.filled:>6d} niches ({100 * p.coverage:5.1f} %)  '
                f'max {p.max:7.3f}  mean {p.mean:7.3f} m  {p.evals_per_s:7.1f} evals/s  '
                f'utilisation {100 * p.utilisation:5.1f} %',
                flush=True,
            )
            return
        if self.bar is None:
            self.bar = tqdm(
                total=self.args.evaluations,
                initial=p.evaluations,
                unit='eval',
                dynamic_ncols=True,
                smoothing=0.1,
            )
        self.bar.update(p.evaluations - self.bar.n)
        self.bar.set_postfix(
            niches=p.filled,
            max=f'{p.max:.3f}',
            util=f'{100 * p.utilisation:.0f}%',
            refresh=False,
        )

    def close(self) -> None:
        """Close the bar, if one was made."""
        if self.bar is not None:
            self.bar.close()


def _generate(args: argparse.Namespace) -> int:
    try:
        config = _config(args)
    except ValueError as exc:
        print(f'generate_map: {exc}', file=sys.stderr)
        return 2
    if (
        not args.resume
    ):  # an existing map, checkpoint or log is the user's: never silently replaced
        claim_outputs(
            [config.out, config.checkpoint_path, config.log_path],
            args.force,
            '--resume to continue it, or --force to start afresh (the old files are kept as'
            ' NAME.bak)',
        )
    show = _Progress(args)
    try:
        archive = generate_map(config, on_progress=show)
    except (EmptyMapError, RuntimeError) as exc:
        print(f'generate_map: {exc}', file=sys.stderr)
        return 1
    finally:
        show.close()
    s = archive.stats()
    if archive.kind.name == 'navigation':
        best = f'median heading change {-s.median:.3f} rad'
    else:
        best = f'max {s.max:.3f} m ({s.max / archive.trial_duration:.3f} m/s)'
    print(
        f'wrote {config.out}: {s.filled} of {archive.n_niches} niches, {best},'
        f' {archive.metadata["evaluations"]} evaluations'
    )
    return 0


if __name__ == '__main__':
    sys.exit(main())
