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
"""
``recover_recording``.

Rewrite an MCAP recording whose writer was killed (SIGKILL, power loss) as a valid, indexed MCAP
that every reader opens, keeping every complete message (every trial the adapt node finished before
the kill).

    ros2 run hexapod_adapt recover_recording adaptation_runs/adapt_20261121_101500.mcap
    recover_recording killed.mcap --out repaired.mcap
"""

from __future__ import annotations

import argparse
import sys

from hexapod_adapt.ros.recording import recover
from hexapod_description.cli import input_file, output_file, run_command


def main(argv: list[str] | None = None) -> int:
    """Run ``recover_recording``; exit status 2 for a missing file, 1 for an I/O error."""
    ap = argparse.ArgumentParser(
        prog='recover_recording',
        description=__doc__.split('\n\n')[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument('recording', type=input_file, help='the MCAP file to recover')
    ap.add_argument(
        '--out',
        type=output_file,
        default=None,
        help='where to write the recovered file (default: replace the input, atomically)',
    )
    args = ap.parse_args(argv)

    def recover_file() -> int:
        result = recover(args.recording, args.out)
        print(f'wrote {result.out}: {result.messages} messages on {result.channels} topics')
        return 0

    return run_command('recover_recording', recover_file)


if __name__ == '__main__':
    sys.exit(main())
