# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``ros2 run hexapod_gait footfall``: footfall diagrams (PNG) of the preset gaits.

footfall --out docs/img            # one PNG per preset, 3 cycles each
footfall --preset wave --cycles 2 --out /tmp
"""

from __future__ import annotations

import argparse
from pathlib import Path
import sys

from hexapod_gait.footfall import plot_footfall
from hexapod_gait.presets import preset, PRESETS
from hexapod_gait.trajectory import SIM_RATE, stance_mask
from hexapod_util.cli import (
    add_force,
    claim_outputs,
    FORCE_HINT,
    number,
    output_dir,
    run_command,
)
import numpy as np


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``footfall``: draw a preset's footfall diagram."""
    parser = argparse.ArgumentParser(description='Draw footfall diagrams of the preset gaits.')
    parser.add_argument(
        '--preset',
        choices=sorted(PRESETS),
        action='append',
        help='preset to draw (repeatable; default: tripod, wave, quadruped)',
    )
    parser.add_argument(
        '--cycles',
        type=number(float, 0, 100, low_open=True),
        default=3.0,
        help='gait cycles to draw, (0, 100]',
    )
    parser.add_argument('--out', type=output_dir, default=Path('.'), help='output directory')
    add_force(parser)
    args = parser.parse_args(argv)
    return run_command('footfall', lambda: _draw(args))


def _draw(args: argparse.Namespace) -> int:
    names = args.preset or ['tripod', 'wave', 'quadruped']
    claim_outputs([args.out / f'footfall_{name}.png' for name in names], args.force, FORCE_HINT)
    for name in names:
        gait = preset(name)
        times = np.arange(int(round(args.cycles * gait.period * SIM_RATE))) / SIM_RATE
        path = plot_footfall(
            stance_mask(gait, times),
            times,
            args.out / f'footfall_{name}.png',
            title=f'{name} gait (controller), duty factor {gait.duty_factor[0]:.3g}',
        )
        print(path)
    return 0


if __name__ == '__main__':
    sys.exit(main())
