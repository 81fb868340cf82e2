# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""``firmware_fuzz``: the differential fuzz of the firmware module (:mod:`.differential`)."""

from __future__ import annotations

import argparse
import sys

from hexapod_bridge.emulator.differential import fuzz, FuzzResult
from hexapod_util.cli import number, run_command


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``firmware_fuzz``: the differential fuzz, in scripts of --chunk frames."""
    parser = argparse.ArgumentParser(
        description='Differential fuzz of the C++ firmware module against the Python model.'
    )
    parser.add_argument('--frames', type=number(int, 1, 10**8), default=100_000)
    parser.add_argument('--seed', type=number(int, 0, 2**31), default=0, help='first seed')
    parser.add_argument(
        '--chunk',
        type=number(int, 1000, 10**7),
        default=100_000,
        help='frames per script (seeds seed, seed + 1, ...)',
    )
    parser.add_argument(
        '--dead-servo', type=number(int, 2, 19), action='append', default=[], metavar='ID'
    )
    args = parser.parse_args(argv)

    def run() -> int:
        total = FuzzResult(0, 0, 0, 0, 0, 0.0, 0.0, 0.0, None)
        seed, left = args.seed, args.frames
        while left > 0:
            n = min(args.chunk, left)
            r = fuzz(seed, n, frozenset(args.dead_servo))
            print(
                f'seed {seed}: {r.frames} frames, {r.events} events, {r.commits_ok} gaits'
                f' committed, {r.trials} walks, {r.tables} tables compared (max error'
                f' {r.max_position_error:.2e} rad, {r.max_velocity_error:.2e} rad/s),'
                f' {r.seconds:.0f} s: {"DIVERGED" if r.divergence else "same output"}',
                flush=True,
            )
            if r.divergence is not None:
                d = r.divergence
                print(f'  first divergence at output line {d.line} (event {d.event}):')
                print(f'  model : {d.model[:300]}')
                print(f'  native: {d.native[:300]}')
                return 1
            total = FuzzResult(
                total.frames + r.frames,
                total.events + r.events,
                total.tables + r.tables,
                total.commits_ok + r.commits_ok,
                total.trials + r.trials,
                total.seconds + r.seconds,
                max(total.max_position_error, r.max_position_error),
                max(total.max_velocity_error, r.max_velocity_error),
                None,
            )
            seed, left = seed + 1, left - n
        print(
            f'TOTAL {total.frames} frames, {total.events} events, {total.commits_ok} gaits'
            f' committed, {total.trials} walks, {total.tables} tables: 0 divergences'
            f' ({total.seconds:.0f} s)'
        )
        return 0

    return run_command('firmware_fuzz', run)


if __name__ == '__main__':
    sys.exit(main())
