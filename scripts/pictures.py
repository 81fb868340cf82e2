#!/usr/bin/env python3
# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
`make pictures`: footfall diagrams and animated GIFs of walks.

Footfall diagrams of the preset gaits (controller), a measured footfall of a simulated tripod
walk, and animated GIFs of simulated walks (PyBullet's headless renderer).

    python scripts/pictures.py --out docs/img [--no-gif]
"""

from __future__ import annotations

import argparse
from pathlib import Path
import sys


def main(argv: list[str] | None = None) -> int:
    from hexapod_gait.footfall_cli import main as footfall_main
    from hexapod_sim.render_walk_cli import render_walk

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--out', type=Path, default=Path('docs/img'))
    parser.add_argument('--no-gif', action='store_true', help='only the footfall diagrams')
    args = parser.parse_args(argv)
    footfall_main(['--out', str(args.out), '--force'])  # pictures are remade
    walks = [('tripod', []), ('wave', [1])]
    for name, failed in walks:
        gif = args.out / (
            f'walk_{name}'
            + (f'_leg{"_".join(map(str, failed))}_failed' if failed else '')
            + '.gif'
        )
        if args.no_gif:
            gif = Path('/tmp') / gif.name
        for path in render_walk(name, 3.0, gif, failed, fps=15):
            print(path)
    return 0


if __name__ == '__main__':
    sys.exit(main())
