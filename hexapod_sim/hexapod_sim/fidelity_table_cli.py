# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``ros2 run hexapod_sim fidelity_table``.

The fidelity table (markdown) for one engine or all of them, and with ``--agreement-map`` how well
each pair of engines agrees over a map's gaits.

    fidelity_table                                   # every engine side by side
    fidelity_table --engine mujoco
    fidelity_table --agreement-map hexapod_adapt/maps/demo_map.npz
"""

from __future__ import annotations

import argparse
import itertools
from pathlib import Path
import sys

from hexapod_sim.fidelity import agreement, fidelity_rows, markdown
from hexapod_sim.physics.engines import create_simulator
from hexapod_sim.simulator import ENGINES, SimConfig
from hexapod_util.cli import input_file, run_command
from hexapod_util.npz import float_array, read_npz, UnreadableFile
import numpy as np


def map_genotypes(path: Path) -> np.ndarray:
    """Return the genotypes of the filled niches of an archive file (written by generate_map)."""
    try:
        data = read_npz(path, ('fitness', 'genotypes'))
        fitness = float_array(data['fitness'], f'{path}: fitness')
        genotypes = float_array(data['genotypes'], f'{path}: genotypes')
    except (OSError, UnreadableFile) as exc:
        raise ValueError(f'not an archive with fitness and genotypes arrays: {exc}') from None
    if fitness.ndim != 1 or genotypes.ndim != 2 or len(fitness) != len(genotypes):
        raise ValueError(
            f'{path}: fitness {fitness.shape} and genotypes {genotypes.shape} do not match'
        )
    return genotypes[np.isfinite(fitness)]


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``fidelity_table``; exit status 2 for an unreadable map."""
    parser = argparse.ArgumentParser(
        description=(
            'Simulated speeds of the reference gaits per failure scenario, '
            "per engine, and the engines' agreement over a map's gaits."
        )
    )
    parser.add_argument(
        '--engine',
        choices=ENGINES + ('all',),
        default='all',
        help='engine to tabulate (default: all of them)',
    )
    parser.add_argument(
        '--agreement-map',
        type=input_file,
        default=None,
        help='archive (.npz) whose gaits each pair of the tabulated engines is compared on',
    )
    args = parser.parse_args(argv)
    return run_command('fidelity_table', lambda: _tabulate(args))


def _tabulate(args: argparse.Namespace) -> int:
    engines = ENGINES if args.engine == 'all' else (args.engine,)
    sims = {name: create_simulator(SimConfig(engine=name)) for name in engines}
    try:
        rows = [row for name in engines for row in fidelity_rows(sims[name])]
        print(markdown(rows))
        if args.agreement_map:
            genotypes = map_genotypes(args.agreement_map)
            for first, second in itertools.combinations(engines, 2):
                a = agreement(genotypes, sims[first], sims[second])
                print(
                    f'\n{first} vs {second} over the {a.gaits} gaits of {args.agreement_map}'
                    f' (collisions not fatal): Spearman {a.spearman:.3f}, mean |descriptor'
                    f' difference| {a.mean_abs_descriptor:.3f}'
                )
    except ValueError as exc:
        print(f'fidelity_table: {exc}', file=sys.stderr)
        return 2
    finally:
        for sim in sims.values():
            sim.close()
    return 0


if __name__ == '__main__':
    sys.exit(main())
