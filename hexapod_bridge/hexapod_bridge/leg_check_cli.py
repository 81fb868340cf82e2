# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``ros2 run hexapod_bridge leg_check``: lift one leg of the robot to check the bridge's leg map.

    leg_check 3 [--arm] [--bridge bridge_node] [--timeout 30]

Uploads through bridge_node a gait that stands still and lifts only URDF leg LEG's foot, once a
second (hexapod_gait.presets.leg_check), and starts one trial (bridge_node's trial_duration).
It prints which leg should lift: where URDF leg LEG is mounted, and the robot's leg number
bridge_node's ``leg_map`` gives it. If another leg lifts, ``leg_map`` is wrong: fix it before
any trial (docs/bridge.md, "Leg numbering").
"""

from __future__ import annotations

import argparse
import math
import sys
import time

from hexapod_description import load_model
from hexapod_gait.presets import leg_check, LEG_CHECK_LIFT
from hexapod_gait.ros_conversions import gait_to_msg
from hexapod_msgs.srv import UploadGait
from hexapod_util import guarded_logging
from hexapod_util.cli import number, run_command
from rcl_interfaces.srv import GetParameters
import rclpy
from rclpy.signals import SignalHandlerOptions
from std_srvs.srv import SetBool, Trigger


def build_parser() -> argparse.ArgumentParser:
    """Return the command-line options of ``leg_check``."""
    ap = argparse.ArgumentParser(
        prog='leg_check',
        description="Lift one URDF leg's foot on the robot, to check bridge_node's leg_map.",
    )
    ap.add_argument('leg', type=number(int, 1, 6), help='the URDF leg to lift, 1..6')
    ap.add_argument('--arm', action='store_true', help='arm bridge_node first (~/arm true)')
    ap.add_argument('--bridge', default='bridge_node', help="bridge_node's name")
    ap.add_argument(
        '--timeout',
        type=number(float, 0, 600, low_open=True),
        default=30.0,
        help='seconds to wait for each answer of bridge_node, (0, 600]',
    )
    return ap


def main(argv: list[str] | None = None) -> int:
    """Parse the options, upload the leg's check gait and start its trial; 0 on success."""
    args, ros_args = build_parser().parse_known_args(argv)
    return run_command('leg_check', lambda: _check(args, ros_args))


def expectation(leg: int, leg_map: list[int] | None) -> str:
    """Say which leg should lift: where URDF leg ``leg`` is, and its robot leg number."""
    mount = load_model().mounts[leg - 1]
    where = (
        f"URDF leg {leg}, mounted at {math.degrees(mount.yaw):+.0f} deg from the body's +x axis"
        ' (counter-clockwise seen from above)'
    )
    robot = (
        f'robot leg {leg_map[leg - 1]} by leg_map {leg_map}'
        if leg_map is not None
        else "robot leg unknown (bridge_node's leg_map could not be read)"
    )
    return (
        f'{where}, {robot}, lifts its foot {LEG_CHECK_LIFT * 100:.0f} cm once a second during'
        ' the trial; every other foot stays down. If another leg lifts, leg_map is wrong.'
    )


def _call(node, client, request, timeout: float):
    """Return the service's answer, or None if it is not there or does not answer in time."""
    if not client.wait_for_service(timeout_sec=timeout):
        return None
    future = client.call_async(request)
    deadline = time.monotonic() + timeout
    while not future.done() and time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.05)
    return future.result() if future.done() else None


def _check(args: argparse.Namespace, ros_args: list[str]) -> int:
    rclpy.init(args=ros_args, signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node('leg_check')
    bridge = args.bridge.rstrip('/')
    try:
        answer = _call(
            node,
            node.create_client(GetParameters, f'{bridge}/get_parameters'),
            GetParameters.Request(names=['leg_map']),
            args.timeout,
        )
        if answer is None:
            print(
                f'leg_check: {bridge} does not answer within {args.timeout:g} s'
                ' (is bridge_node running?)',
                file=sys.stderr,
            )
            return 1
        values = answer.values[0].integer_array_value if answer.values else []
        leg_map = [int(v) for v in values] if len(values) == 6 else None
        if args.arm:
            armed = _call(
                node,
                node.create_client(SetBool, f'{bridge}/arm'),
                SetBool.Request(data=True),
                args.timeout,
            )
            if armed is None or not armed.success:
                print(f'leg_check: {bridge} could not be armed', file=sys.stderr)
                return 1
        uploaded = _call(
            node,
            node.create_client(UploadGait, f'{bridge}/upload_gait'),
            UploadGait.Request(gait=gait_to_msg(leg_check(args.leg)), timeout=args.timeout),
            args.timeout + 5.0,
        )
        if uploaded is None or not uploaded.success:
            why = uploaded.message if uploaded is not None else 'no answer'
            print(f'leg_check: the check gait was not uploaded: {why}', file=sys.stderr)
            return 1
        started = _call(
            node,
            node.create_client(Trigger, f'{bridge}/start_trial'),
            Trigger.Request(),
            args.timeout,
        )
        if started is None or not started.success:
            why = started.message if started is not None else 'no answer'
            print(f'leg_check: the trial did not start: {why}', file=sys.stderr)
            return 1
        print(f'{started.message}: {expectation(args.leg, leg_map)}', flush=True)
        return 0
    finally:
        node.destroy_node()
        guarded_logging.shutdown()


if __name__ == '__main__':
    sys.exit(main())
