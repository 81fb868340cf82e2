# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
r"""
Choose and measure the gaits made for a damage (:mod:`hexapod_navigation.core.specialists`).

    python -m hexapod_navigation.offline.specialists_cli \\
        --out hexapod_navigation/maps/navigation_specialists.npz --workers 2
"""

from __future__ import annotations

import argparse
import sys
import time

from hexapod_adapt import load_archive, shipped_ceilings, shipped_map
from hexapod_navigation.core.repertoire import Repertoire, shipped_repertoire
from hexapod_navigation.core.specialists import compute_specialists, save_specialists, SOURCE_KINDS
from hexapod_navigation.core.step_bank import load_step_bank, shipped_step_bank
from hexapod_sim.damage import DAMAGE_KINDS
from hexapod_util.cli import (
    add_force,
    claim_outputs,
    FORCE_HINT,
    input_file,
    number,
    output_file,
    run_command,
)


def main(argv: list[str] | None = None) -> int:
    """Compute the specialists of a map for a repertoire's bank and write them."""
    ap = argparse.ArgumentParser(
        prog='specialists',
        description="Choose the map's fastest gait under each of the bank's damages and measure"
        ' it as navigation steps.',
    )
    ap.add_argument(
        '--map', type=input_file, default=None, help='adaptation map (default: the shipped one)'
    )
    ap.add_argument(
        '--ceilings',
        type=input_file,
        default=None,
        help="the map's ceilings folder (default: the shipped one)",
    )
    ap.add_argument('--repertoire', type=input_file, default=None, help='default: the shipped one')
    ap.add_argument(
        '--bank', type=input_file, default=None, help="the repertoire's bank (default: shipped)"
    )
    ap.add_argument(
        '--min-stance-legs',
        type=number(int, 0, 6),
        default=3,
        help='only gaits with this many feet down throughout (the repertoire rule)',
    )
    ap.add_argument(
        '--source-kinds',
        nargs='+',
        choices=DAMAGE_KINDS,
        default=list(SOURCE_KINDS),
        help="make gaits for the bank's damages of these kinds (and the intact robot)",
    )
    ap.add_argument('--out', type=output_file, required=True, help='the file (.npz)')
    ap.add_argument('--workers', type=number(int, 1, 256), default=1)
    add_force(ap)
    args = ap.parse_args(argv)

    def run() -> int:
        claim_outputs([args.out], args.force, FORCE_HINT)
        archive = load_archive(args.map or shipped_map())
        repertoire = Repertoire.from_archive(load_archive(args.repertoire or shipped_repertoire()))
        bank, problem = load_step_bank(
            args.bank or shipped_step_bank(), repertoire, repertoire.engine
        )
        if bank is None:
            print(f'specialists: {problem}', file=sys.stderr)
            return 2
        t0 = time.monotonic()

        def progress(done: int, total: int) -> None:
            print(f'{done}/{total} damages, {time.monotonic() - t0:.0f} s', flush=True)

        sp = compute_specialists(
            archive,
            bank.damages,
            repertoire.engine,
            repertoire.step_duration,
            [args.ceilings or shipped_ceilings()],
            args.min_stance_legs,
            args.workers,
            progress,
            args.source_kinds,
        )
        save_specialists(
            args.out, sp, repertoire.engine, archive, args.min_stance_legs, args.source_kinds
        )
        print(f'wrote {args.out}: {len(sp)} steps x {len(bank)} damages', flush=True)
        return 0

    return run_command('specialists', run, 'nothing was written; run it again')


if __name__ == '__main__':
    sys.exit(main())
