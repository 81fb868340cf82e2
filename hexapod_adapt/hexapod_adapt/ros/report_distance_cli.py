# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``ros2 run hexapod_adapt report_distance METRES``: answer a manual trial's prompt.

In manual mode (the thesis's tape measure) adapt_node starts each trial's walk through
bridge_node and, once it ended, asks for the distance walked along the gait's walking direction
(adapt_client prints the prompt). This sends it to adapt_node's ``~/report_distance``:

    report_distance 0.62      # metres; 0 (it did not move) and negative (backwards) are answers

Exit status 0 when adapt_node took it, 1 when it refused it (the reason is printed: no trial
waiting, a distance that is not plausible), 2 for bad usage.
"""

from __future__ import annotations

import argparse
import sys

from hexapod_adapt.ros.adapt_service_cli import exit_status, node_options
from hexapod_msgs.srv import ReportDistance
from hexapod_util.cli import number, run_command
from hexapod_util.ros_glue import call_service_once


def build_parser() -> argparse.ArgumentParser:
    """Return the command-line options of ``report_distance``."""
    ap = argparse.ArgumentParser(
        prog='report_distance', description="Report a manual trial's tape-measured distance."
    )
    ap.add_argument(
        'distance',
        type=number(float),
        help='metres walked along the walking direction (0: it did not move; negative: backwards)',
    )
    node_options(ap, 10.0)
    return ap


def main(argv: list[str] | None = None) -> int:
    """Parse the options, send the distance, print the answer."""
    args, ros_args = build_parser().parse_known_args(argv)
    return run_command('report_distance', lambda: _call(args, ros_args))


def _call(args: argparse.Namespace, ros_args: list[str]) -> int:
    answer = call_service_once(
        'report_distance', ReportDistance, f'{args.node}/report_distance',
        ReportDistance.Request(distance=args.distance), args.timeout, ros_args,
        'is adapt_node running, in manual mode?',
    )  # fmt: skip
    done = None if answer is None else answer.accepted
    return exit_status('report_distance', done, '' if answer is None else answer.message)


if __name__ == '__main__':
    sys.exit(main())
