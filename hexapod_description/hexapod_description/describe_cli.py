# Copyright 2026 Hexapod adaptation team
# All rights reserved.
#
# Permission is hereby granted, free of charge, to any person obtaining a copy
# of this software and associated documentation files (the "Software"), to deal
# in the Software without restriction, including without limitation the rights
# to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
# copies of the Software, and to permit persons to whom the Software is
# furnished to do so, subject to the following conditions:
#
# The above copyright notice and this permission notice shall be included in all
# copies or substantial portions of the Software.
#
# THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
# IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
# FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
# AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
# LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
# OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
# SOFTWARE.
"""``ros2 run hexapod_description describe``: print a summary of the hexapod model."""

from __future__ import annotations

import argparse
import sys

from hexapod_description.cli import input_file, run_command
from hexapod_description.model import load_model, summary


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
