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
import time

from hexapod_msgs.srv import ReportDistance
from hexapod_util.cli import number, run_command
from hexapod_util.ros_glue import spin_until_done, try_shutdown, Waited
import rclpy
from rclpy.signals import SignalHandlerOptions


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
    ap.add_argument('--node', default='adapt_node', help='name of the adapt node')
    ap.add_argument(
        '--timeout',
        type=number(float, 0, 3600, low_open=True),
        default=10.0,
        help='give up after this many seconds, waiting for the node included',
    )
    return ap


def main(argv: list[str] | None = None) -> int:
    """Parse the options, send the distance, print the answer."""
    args, ros_args = build_parser().parse_known_args(argv)
    return run_command('report_distance', lambda: _call(args, ros_args))


def _call(args: argparse.Namespace, ros_args: list[str]) -> int:
    deadline = time.monotonic() + args.timeout
    rclpy.init(args=ros_args, signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node('report_distance')
    try:
        client = node.create_client(ReportDistance, f'{args.node}/report_distance')
        if not client.wait_for_service(timeout_sec=args.timeout):
            print(
                f'report_distance: {client.srv_name} not available within {args.timeout:g} s'
                ' (is adapt_node running, in manual mode?)',
                file=sys.stderr,
            )
            return 1
        future = client.call_async(ReportDistance.Request(distance=args.distance))
        if spin_until_done(node, future, deadline, client.service_is_ready) is not Waited.DONE:
            print(f'report_distance: no answer within {args.timeout:g} s', file=sys.stderr)
            return 1
        answer = future.result()
        if answer.accepted:
            print(answer.message)
            return 0
        print(f'report_distance: refused: {answer.message}', file=sys.stderr)
        return 1
    finally:
        node.destroy_node()
        try_shutdown()


if __name__ == '__main__':
    sys.exit(main())
