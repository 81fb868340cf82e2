# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""``ros2 run hexapod_description describe``: print a summary of the hexapod model."""

from __future__ import annotations

import argparse
import sys

from hexapod_description.model import load_model, summary
from hexapod_util.cli import input_file, run_command


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``describe``: print the robot model read from the URDF."""
    parser = argparse.ArgumentParser(description='Print a summary of the hexapod URDF.')
    parser.add_argument(
        '--urdf', type=input_file, help='URDF to read (default: the installed one)'
    )
    parser.add_argument('--print-urdf-path', action='store_true', help='print only the path')
    args = parser.parse_args(argv)

    def describe() -> int:
        model = load_model(args.urdf)
        print(model.path if args.print_urdf_path else summary(model))
        return 0

    return run_command('describe', describe)


if __name__ == '__main__':
    sys.exit(main())
