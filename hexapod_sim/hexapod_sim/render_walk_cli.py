# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``ros2 run hexapod_sim render_walk``.

Render a simulated walk to an animated GIF (PyBullet's headless TinyRenderer, or MuJoCo's OpenGL
renderer with ``--engine mujoco``, which needs MUJOCO_GL=egl or osmesa on a machine without a
display), and draw its measured footfall (PNG).

    render_walk --preset tripod --seconds 3 --out docs/img/walk_tripod.gif
    render_walk --preset wave --failed-legs 1 --out /tmp/wave_s1.gif
"""

from __future__ import annotations

import argparse
from pathlib import Path
import sys

from hexapod_description import N_LEGS
from hexapod_gait import build_joint_table, preset, PRESETS
from hexapod_gait.footfall import plot_footfall
from hexapod_sim.physics.engines import create_simulator
from hexapod_sim.simulator import ENGINES, SimConfig
from hexapod_util.cli import (
    add_force,
    claim_outputs,
    FORCE_HINT,
    number,
    output_file,
    run_command,
)
import numpy as np


def render_walk(
    gait_name: str,
    seconds: float,
    out: Path,
    failed_legs: list[int],
    fps: int = 20,
    size: tuple[int, int] = (400, 300),
    engine: str = 'pybullet',
) -> tuple[Path, Path]:
    """Write ``out`` (GIF) and ``<out>_footfall.png``; returns both paths."""
    from PIL import Image  # matplotlib's dependency; only this tool needs it

    gait = preset(gait_name)
    with create_simulator(SimConfig(engine=engine)) as sim:
        sim.set_failed_legs(failed_legs)
        table = build_joint_table(gait, rate=1.0 / sim.dt)
        rows = sim.prepare_rows(table.positions, table.velocities)
        sim.reset(table.positions[0])
        steps = int(round(seconds / sim.dt))
        every = max(1, int(round(1.0 / (fps * sim.dt))))
        frames, contacts = [], np.zeros((steps, 6), dtype=bool)
        for k in range(steps):
            row = k % len(table)
            sim.apply_row(rows, row)
            contacts[k] = sim.step().contacts
            if k % every == 0:
                frames.append(Image.fromarray(sim.render(*size)))
    out.parent.mkdir(parents=True, exist_ok=True)
    frames[0].save(out, save_all=True, append_images=frames[1:], duration=int(1000 / fps), loop=0)
    times = np.arange(steps) * sim.dt
    failed = f', legs {failed_legs} failed' if failed_legs else ''
    footfall = plot_footfall(
        contacts,
        times,
        out.with_name(out.stem + '_footfall.png'),
        title=f'{gait_name} gait, measured foot contacts in simulation{failed}',
    )
    return out, footfall


def main(argv: list[str] | None = None) -> int:
    """Run ``render_walk``; exit status 2 for bad options or an engine that cannot render."""
    parser = argparse.ArgumentParser(
        description='Render a simulated walk to GIF + measured footfall PNG.'
    )
    parser.add_argument('--preset', choices=sorted(PRESETS), default='tripod', help='gait to walk')
    parser.add_argument(
        '--seconds',
        type=number(float, 0, 60, low_open=True),
        default=3.0,
        help='simulated seconds, (0, 60]',
    )
    parser.add_argument(
        '--failed-legs',
        type=number(int, 1, N_LEGS),
        nargs='*',
        default=[],
        help='legs 1..6 to fail (at most two)',
    )
    parser.add_argument(
        '--fps', type=number(int, 1, 60), default=20, help='GIF frames per second, 1..60'
    )
    parser.add_argument('--engine', choices=ENGINES, default='pybullet', help='physics engine')
    parser.add_argument('--out', type=output_file, default=Path('walk.gif'), help='GIF to write')
    add_force(parser)
    args = parser.parse_args(argv)

    def render() -> int:
        footfall = args.out.with_name(args.out.stem + '_footfall.png')
        claim_outputs([args.out, footfall], args.force, FORCE_HINT)
        try:
            gif, png = render_walk(
                args.preset, args.seconds, args.out, args.failed_legs, args.fps, engine=args.engine
            )
        except RuntimeError as exc:  # an engine that cannot render here
            print(f'render_walk: {exc}', file=sys.stderr)
            return 2
        print(gif)
        print(png)
        return 0

    return run_command('render_walk', render)


if __name__ == '__main__':
    sys.exit(main())
