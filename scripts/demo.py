#!/usr/bin/env python3
"""`make demo`: what the product can do so far, end to end, in about a minute.

1. The hexapod model from the URDF (mass, link lengths, limits).
2. The gait controller: the preset gaits and their footfall patterns.
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np


def main() -> int:
    from hexapod_description import load_model, summary
    from hexapod_gait import PRESETS, build_joint_table, preset, stance_mask
    from hexapod_gait.footfall import plot_footfall, swing_groups

    out = Path("out/demo")
    out.mkdir(parents=True, exist_ok=True)
    print("== hexapod model (hexapod_description) ==")
    print(summary(load_model()))
    print("\n== gait controller (hexapod_gait) ==")
    for name in PRESETS:
        gait = preset(name)
        t0 = time.perf_counter()
        table = build_joint_table(gait)
        ms = (time.perf_counter() - t0) * 1e3
        times = np.arange(3 * len(table)) / table.rate
        groups = " -> ".join("{" + ",".join(map(str, sorted(g))) + "}"
                             for g in swing_groups(stance_mask(gait, times)))
        png = plot_footfall(stance_mask(gait, times), times, out / f"footfall_{name}.png", title=name)
        print(f"{name:9s} v={gait.body_velocity:.3f} m/s  duty={gait.duty_factor[0]:.3f}  "
              f"table {table.positions.shape} in {ms:.2f} ms  swing order {groups}  -> {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
