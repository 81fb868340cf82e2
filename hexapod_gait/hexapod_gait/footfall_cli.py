"""``ros2 run hexapod_gait footfall``: footfall diagrams (PNG) of the preset gaits.

    footfall --out docs/img            # one PNG per preset, 3 cycles each
    footfall --preset wave --cycles 2 --out /tmp
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from hexapod_gait.footfall import plot_footfall
from hexapod_gait.presets import PRESETS, preset
from hexapod_gait.trajectory import SIM_RATE, stance_mask


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``footfall``: draw a preset's footfall diagram."""
    parser = argparse.ArgumentParser(description="Draw footfall diagrams of the preset gaits.")
    parser.add_argument("--preset", choices=sorted(PRESETS), action="append",
                        help="preset to draw (repeatable; default: tripod, wave, quadruped)")
    parser.add_argument("--cycles", type=float, default=3.0, help="gait cycles to draw")
    parser.add_argument("--out", type=Path, default=Path("."), help="output directory")
    args = parser.parse_args(argv)
    if args.cycles <= 0:
        parser.error("--cycles must be positive")
    for name in args.preset or ["tripod", "wave", "quadruped"]:
        gait = preset(name)
        times = np.arange(int(round(args.cycles * gait.period * SIM_RATE))) / SIM_RATE
        path = plot_footfall(stance_mask(gait, times), times, args.out / f"footfall_{name}.png",
                             title=f"{name} gait (controller), duty factor {gait.duty_factor[0]:.3g}")
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
