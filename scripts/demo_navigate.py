#!/usr/bin/env python3
# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
`make demo-navigate`: a robot with two dead legs walks to three places by itself.

sim_node (MuJoCo, legs 1 and 2 failed: scenario S4), gait_node, state_publisher and navigate_node
run as separate processes; this script is the operator's action client. The three goals lie
around the robot; navigate_node learns how the damage changes its repertoire's steps as it
walks, and carries what it learned from goal to goal. Each goal is recorded to an MCAP file (the
path, the goal marker, the URDF and frames: it replays in Foxglove's 3D panel), read back here.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path
import signal
import subprocess
import sys
import time

T0 = time.perf_counter()
WS = Path(__file__).resolve().parent.parent
FAILED_LEGS = [1, 2]  # scenario S4: two adjacent legs
GOALS = ((1.5, 0.5), (0.0, 2.0), (-1.0, -0.5))  # m, in odom, one after another


def exe(pkg: str, name: str) -> str:
    return str(WS / 'install' / pkg / 'lib' / pkg / name)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--out', type=Path, default=WS / 'out' / 'demo_navigate')
    out = parser.parse_args(argv).out
    out.mkdir(parents=True, exist_ok=True)
    from hexapod_navigation.ros.navigate_msgs import goal_at, navigate_client
    from hexapod_util import guarded_logging
    from hexapod_util.processes import die_with_parent
    from hexapod_util.recording import read_messages
    from hexapod_util.ros_glue import ros_args
    import rclpy

    domain = 60 + os.getpid() % 30
    env = dict(
        os.environ,
        ROS_DOMAIN_ID=str(domain),
        ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST',
        PYTHONUNBUFFERED='1',
    )
    logs: list = []

    def start(pkg: str, name: str, **params) -> subprocess.Popen:
        logs.append(open(out / f'{name}.log', 'w'))
        return subprocess.Popen(
            [exe(pkg, name), *ros_args(params)],
            env=env,
            stdout=logs[-1],
            stderr=subprocess.STDOUT,
            preexec_fn=die_with_parent,
        )

    nodes = [
        start(
            'hexapod_sim',
            'sim_node',
            engine='mujoco',
            real_time_factor=1.0,  # as launch.py navigate-sim and the launch file: real time
            failed_legs=FAILED_LEGS,
        ),
        start('hexapod_gait', 'gait_node', initial_preset='', use_sim_time=True),
        start('hexapod_gait', 'state_publisher', use_sim_time=True),
        start(
            'hexapod_navigation', 'navigate_node', record_dir=str(out / 'runs'), use_sim_time=True
        ),
    ]
    print(
        f'legs {FAILED_LEGS[0]} and {FAILED_LEGS[1]} failed; goals {GOALS} (m, odom)', flush=True
    )
    status = 0
    rclpy.init(domain_id=domain)
    node = rclpy.create_node('demo_operator')
    try:
        client = navigate_client(node)
        if not client.wait_for_server(timeout_sec=60):
            print(f'navigate_node did not come up; logs in {out}/')
            return 1
        for x, y in GOALS:
            sent = client.send_goal_async(
                goal_at(x, y),
                feedback_callback=lambda m: print(
                    f'  step {m.feedback.steps}: {m.feedback.distance_remaining:.2f} m left,'
                    f' prediction error {m.feedback.prediction_error:.2f} m',
                    flush=True,
                ),
            )
            rclpy.spin_until_future_complete(node, sent, timeout_sec=60)
            handle = sent.result()
            if handle is None or not handle.accepted:
                print(f'goal ({x}, {y}) rejected: see {out}/navigate_node.log')
                status = 1
                break
            done = handle.get_result_async()
            rclpy.spin_until_future_complete(node, done, timeout_sec=600)
            r = done.result().result
            print(
                f'goal ({x:+.1f}, {y:+.1f}): {r.reason}; {r.walking_time:.1f} s of walking,'
                f' {r.steps} steps, path {r.path_length:.2f} m',
                flush=True,
            )
            if r.recording:
                counts: dict[str, int] = {}
                for topic, _, _ in read_messages(r.recording):
                    counts[topic] = counts.get(topic, 0) + 1
                shown = Path(r.recording)
                shown = shown.relative_to(WS) if shown.is_relative_to(WS) else shown
                print(
                    f'  recorded {shown}: '
                    + ', '.join(f'{n} x {t}' for t, n in sorted(counts.items()))
                )
            status = status or (0 if r.reached else 3)
    finally:
        node.destroy_node()
        guarded_logging.shutdown()
        for p in nodes:
            p.send_signal(signal.SIGINT)
        for p in nodes:
            try:
                p.wait(10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        for f in logs:
            f.close()
    print(f'\ndemo finished in {time.perf_counter() - T0:.0f} s; node logs in {out}/')
    return status


if __name__ == '__main__':
    sys.exit(main())
