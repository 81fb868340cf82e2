# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``ros2 run hexapod_adapt adapt_service calibrate|forget``: call one of adapt_node's services.

    adapt_service calibrate   # the last run walked the intact robot: measure its gap to the
                              # map's engine, write adapt_node's gap_calibration file
    adapt_service forget      # after a repair: drop the servo reports adapt_node holds

The same as ``ros2 service call /adapt_node/<service> std_srvs/srv/Trigger`` on a full ROS
install. Exit status 0 when adapt_node did it, 1 when it refused (the reason is printed) or did
not answer, 2 for bad usage.
"""

from __future__ import annotations

import argparse
import sys

from hexapod_util.cli import number, run_command
from hexapod_util.ros_glue import call_service_once
from std_srvs.srv import Trigger

#: What each service does, for --help.
SERVICES = {
    'calibrate': "measure the robot's gap to the map's engine from the last run, walked intact",
    'forget': 'drop the servo reports adapt_node holds (after a repair)',
}


def build_parser() -> argparse.ArgumentParser:
    """Return the command-line options of ``adapt_service``."""
    ap = argparse.ArgumentParser(
        prog='adapt_service',
        description="Call one of adapt_node's services: "
        + '; '.join(f'{k}: {v}' for k, v in SERVICES.items()),
    )
    ap.add_argument('service', choices=sorted(SERVICES), help='the service to call')
    node_options(ap, 60.0)
    return ap


def node_options(ap: argparse.ArgumentParser, timeout: float) -> None:
    """Add the options of a command that calls adapt_node: its name, how long to wait."""
    ap.add_argument('--node', default='adapt_node', help='name of the adapt node')
    ap.add_argument(
        '--timeout',
        type=number(float, 0, 3600, low_open=True),
        default=timeout,
        help='give up after this many seconds, waiting for the node included',
    )


def exit_status(prog: str, done: bool | None, message: str) -> int:
    """Print adapt_node's answer; return the exit status (None: it did not answer, said)."""
    if done is None:
        return 1
    if done:
        print(message)
        return 0
    print(f'{prog}: refused: {message}', file=sys.stderr)
    return 1


def main(argv: list[str] | None = None) -> int:
    """Parse the options, call the service, print the answer."""
    args, ros_args = build_parser().parse_known_args(argv)
    return run_command('adapt_service', lambda: _call(args, ros_args))


def _call(args: argparse.Namespace, ros_args: list[str]) -> int:
    answer = call_service_once(
        'adapt_service', Trigger, f'{args.node}/{args.service}', Trigger.Request(),
        args.timeout, ros_args, 'is adapt_node running?',
    )  # fmt: skip
    done = None if answer is None else answer.success
    return exit_status('adapt_service', done, '' if answer is None else answer.message)


if __name__ == '__main__':
    sys.exit(main())
