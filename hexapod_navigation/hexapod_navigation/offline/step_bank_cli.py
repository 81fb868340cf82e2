# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
r"""
Make a repertoire's damage bank (:mod:`hexapod_navigation.core.step_bank`).

    python -m hexapod_navigation.offline.step_bank_cli --engine mujoco \\
        --out hexapod_navigation/maps/navigation_bank.npz --workers 2
"""

from __future__ import annotations

import argparse
import sys
import time

from hexapod_adapt import load_archive
from hexapod_navigation.core.repertoire import Repertoire, shipped_repertoire
from hexapod_navigation.core.step_bank import (
    compute_step_bank,
    navigation_bank_damages,
    NAVIGATION_BANK_KINDS,
    save_step_bank,
)
from hexapod_sim import ENGINES
from hexapod_sim.damage import EXPERIMENT_KINDS
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
    """Compute a repertoire's step bank and write it."""
    ap = argparse.ArgumentParser(
        prog='step_bank',
        description='Re-measure every repertoire step under each damage of the bank.',
    )
    ap.add_argument(
        '--repertoire',
        type=input_file,
        default=None,
        help='navigation repertoire (default: the shipped one)',
    )
    ap.add_argument('--engine', choices=ENGINES, default='mujoco')
    ap.add_argument('--out', type=output_file, required=True, help='the bank file (.npz)')
    ap.add_argument(
        '--kinds',
        nargs='+',
        choices=EXPERIMENT_KINDS,
        default=list(NAVIGATION_BANK_KINDS),
        help='damage kinds, each over every one- and two-leg failure of S1-S4'
        f' (default: {" ".join(NAVIGATION_BANK_KINDS)})',
    )
    ap.add_argument('--workers', type=number(int, 1, 256), default=1)
    add_force(ap)
    args = ap.parse_args(argv)

    def run() -> int:
        claim_outputs([args.out], args.force, FORCE_HINT)
        repertoire = Repertoire.from_archive(load_archive(args.repertoire or shipped_repertoire()))
        t0, shown = time.monotonic(), [0.0]

        def progress(done: int, total: int) -> None:
            if time.monotonic() - shown[0] >= 10 or done == total:
                shown[0] = time.monotonic()
                print(f'{done}/{total} chunks, {time.monotonic() - t0:.0f} s', flush=True)

        damages = navigation_bank_damages(tuple(dict.fromkeys(args.kinds)))
        bank = compute_step_bank(
            repertoire, args.engine, damages, workers=args.workers, progress=progress
        )
        save_step_bank(args.out, bank, repertoire, args.engine)
        print(f'wrote {args.out}: {len(bank)} damages x {len(repertoire)} steps', flush=True)
        return 0

    return run_command('step_bank', run, 'nothing was written; run it again')


if __name__ == '__main__':
    sys.exit(main())
