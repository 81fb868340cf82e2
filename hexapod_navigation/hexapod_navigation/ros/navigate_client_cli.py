# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``ros2 run hexapod_adapt navigate_client X Y``.

Send a goal to the ``navigate`` action from a base-station PC, print its feedback after every
step and its result (the same as ``ros2 action send_goal --feedback /navigate
hexapod_msgs/action/Navigate "{pose: {header: {frame_id: odom}, pose: {position: {x: X, y: Y}}}}"``
on a full ROS install: the goal is a PoseStamped, X Y its position in odom). Ctrl-C cancels the
goal, then exits.

    navigate_client 1.5 0.5 [--tolerance 0.15] [--time-limit 90]

Exit status 0 when the goal is reached, 3 when the navigation ended without reaching it, 4 when
the node rejected the goal (its reason is on ``navigate/status``), 1 when no server answered.
"""

from __future__ import annotations

import argparse
import sys
import time

from hexapod_msgs.action import Navigate
from hexapod_navigation.ros.navigate_msgs import goal_at, navigate_client
from hexapod_util import guarded_logging
from hexapod_util.cli import acknowledge_stop, number, run_command
from hexapod_util.ros_glue import spin_until_done, Waited
import rclpy
from rclpy.signals import SignalHandlerOptions

OUTCOMES = {
    getattr(Navigate.Result, name): name
    for name in ('REACHED', 'TIME_LIMIT', 'LEFT_ARENA', 'CANCELED', 'PREEMPTED', 'FAILED')
}


def build_parser() -> argparse.ArgumentParser:
    """Return the command-line options of ``navigate_client``."""
    ap = argparse.ArgumentParser(
        prog='navigate_client', description='Walk the robot to (x, y) in odom; print each step.'
    )
    ap.add_argument('x', type=number(float), help='goal x in odom [m]')
    ap.add_argument('y', type=number(float), help='goal y in odom [m]')
    ap.add_argument(
        '--tolerance',
        type=number(float, 0, 10),
        default=0.0,
        help="reached within this distance [m] (0 = the node's default)",
    )
    ap.add_argument(
        '--time-limit',
        type=number(float, 0, 3600),
        default=0.0,
        help="seconds of walking allowed (0 = the node's default)",
    )
    ap.add_argument('--action', default='navigate', help='name of the navigate action')
    ap.add_argument(
        '--timeout',
        type=number(float, 0, 10**6, low_open=True),
        default=3600.0,
        help='give up after this many seconds, waiting for the server included',
    )
    return ap


def main(argv: list[str] | None = None) -> int:
    """Parse the options, send the goal, print feedback and the result."""
    args, ros_args = build_parser().parse_known_args(argv)
    return run_command(
        'navigate_client', lambda: _send(args, ros_args), 'the goal was cancelled first'
    )


def _server_gone(action: str) -> int:
    print(
        f'navigate_client: the server of {action} shut down before it answered'
        ' (navigate_node stopped mid-goal; its recording holds the steps it walked)',
        file=sys.stderr,
    )
    return 1


def _send(args: argparse.Namespace, ros_args: list[str]) -> int:
    deadline = time.monotonic() + args.timeout
    rclpy.init(args=ros_args, signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node('navigate_client')
    handle = None
    try:
        client = navigate_client(node, args.action)
        if not client.wait_for_server(timeout_sec=max(0.0, deadline - time.monotonic())):
            print(
                f'navigate_client: action {args.action} not available within {args.timeout:g} s'
                ' (is navigate_node running?)',
                file=sys.stderr,
            )
            return 1

        def show(msg) -> None:
            f = msg.feedback
            p = f.current_pose.pose.position
            print(
                f'step {f.steps:>3d}: at ({p.x:+.2f}, {p.y:+.2f}), {f.distance_remaining:.2f} m'
                f' left, prediction error {f.prediction_error:.2f} m,'
                f' {f.navigation_time.sec + f.navigation_time.nanosec * 1e-9:.1f} s walked',
                flush=True,
            )

        goal = goal_at(args.x, args.y, tolerance=args.tolerance, time_limit=args.time_limit)
        sent = client.send_goal_async(goal, feedback_callback=show)
        if spin_until_done(node, sent, deadline, client.server_is_ready) is Waited.SERVER_GONE:
            return _server_gone(args.action)
        handle = sent.result() if sent.done() else None
        if handle is None:
            print(f'navigate_client: no answer within {args.timeout:g} s', file=sys.stderr)
            return 1
        if not handle.accepted:
            print(
                f'navigate_client: goal ({args.x}, {args.y}) rejected; the reason is on'
                ' navigate/status and in the node log',
                file=sys.stderr,
            )
            return 4
        done = handle.get_result_async()
        if spin_until_done(node, done, deadline, client.server_is_ready) is Waited.SERVER_GONE:
            handle = None  # no server left to cancel the goal on
            return _server_gone(args.action)
        if not done.done():
            print(f'navigate_client: no result within {args.timeout:g} s', file=sys.stderr)
            return 1
        r = done.result().result
        print(
            f'{OUTCOMES.get(r.outcome, r.outcome)}: {r.reason}; {r.walking_time:.1f} s of walking,'
            f' {r.steps} steps, path {r.path_length:.2f} m, {r.distance_left:.2f} m from the goal'
        )
        if r.recording:
            print(f'recording: {r.recording}')
        handle = None
        return 0 if r.reached else 3
    except KeyboardInterrupt:  # Ctrl-C or SIGTERM: cancel the goal before leaving
        acknowledge_stop()
        if handle is not None:
            cancel = handle.cancel_goal_async()
            end = time.monotonic() + 5.0
            while not cancel.done() and time.monotonic() < end:
                rclpy.spin_once(node, timeout_sec=0.1)
        raise
    finally:
        node.destroy_node()
        guarded_logging.shutdown()


if __name__ == '__main__':
    sys.exit(main())
