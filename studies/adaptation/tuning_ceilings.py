# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The tuning set's ceilings: every gait of the tuning map under each tuning damage case, cached.

    python -m studies.adaptation.tuning_ceilings \
        --archive studies/out/tuning_map_s2.npz --cache-dir studies/out/ceilings
"""

from __future__ import annotations

import argparse
import sys
import time

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.online.ceiling import ceiling
from hexapod_sim import ENGINES
from hexapod_util.cli import input_file, number, output_dir, run_command
from studies.tuning_set import TUNING_DAMAGES


def main(argv: list[str] | None = None) -> int:
    """Compute (or find in the cache) the ceiling of every tuning case; a line each."""
    ap = argparse.ArgumentParser(prog='tuning_ceilings', description=__doc__.split('\n\n')[0])
    ap.add_argument('--archive', type=input_file, required=True, help='the tuning map')
    ap.add_argument('--engine', choices=ENGINES, default='mujoco', help='trial engine')
    ap.add_argument(
        '--cache-dir', type=output_dir, required=True, help='where ceilings are cached'
    )
    ap.add_argument('--workers', type=number(int, 1, 256), default=1, help='worker processes')
    args = ap.parse_args(argv)

    def run() -> int:
        archive = load_archive(args.archive)
        for damage in TUNING_DAMAGES:
            t0 = time.monotonic()
            c = ceiling(archive, damage, args.engine, args.cache_dir, args.workers)
            print(
                f'{args.engine} tuning {damage.label}: ceiling {c.best_speed:.3f} m/s'
                f' (gait {c.best_niche}), {len(c.speeds)} gaits, {time.monotonic() - t0:.0f} s',
                flush=True,
            )
        return 0

    return run_command(
        'tuning_ceilings', run, 'finished damage cases are cached; run again to go on'
    )


if __name__ == '__main__':
    sys.exit(main())
