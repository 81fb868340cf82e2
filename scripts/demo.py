#!/usr/bin/env python3
"""`make demo`: what the product can do so far, end to end, in about half a minute.

1. The hexapod model from the URDF (mass, link lengths, limits).
2. The gait controller: the preset gaits, their footfall patterns (PNG in out/demo/).
3. The simulator: speed of the control gait intact and with leg failures (fidelity table).
4. The ROS graph: gait_node + sim_node as separate processes; one 5 s trial of the wave gait
   through the graph, compared with the library's evaluation of the same gait.
(The adaptation demo replaces this when map generation and M-BOA exist.)
"""
from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

WS = Path(__file__).resolve().parent.parent


def section(title: str) -> None:
    print(f"\n== {title} ==", flush=True)


def graph_trial(gait) -> float:
    """Speed of one trial of ``gait`` through gait_node + sim_node (fast mode)."""
    import rclpy
    from hexapod_msgs.msg import GaitParameters as GaitParametersMsg
    from nav_msgs.msg import Odometry
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
    from std_msgs.msg import Header
    from std_srvs.srv import Trigger

    from hexapod_gait.ros_conversions import gait_to_msg

    env = dict(os.environ, ROS_DOMAIN_ID=str(60 + os.getpid() % 30), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST")
    os.environ.update(env)
    procs = [subprocess.Popen([str(WS / "install/hexapod_gait/lib/hexapod_gait/gait_node"), "--ros-args", "-p",
                               "initial_preset:=''"], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL),
             subprocess.Popen([str(WS / "install/hexapod_sim/lib/hexapod_sim/sim_node"), "--ros-args", "-p",
                               "real_time_factor:=0.0", "-p", "publish_period_steps:=24"], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    rclpy.init()
    node = rclpy.create_node("demo")
    latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE)
    odom, active, resets = [], [], []
    node.create_subscription(Odometry, "odom", odom.append, QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE))
    node.create_subscription(Header, "sim/active_trajectory", active.append, latched)
    node.create_subscription(Header, "sim/last_reset", resets.append, latched)
    pub = node.create_publisher(GaitParametersMsg, "gait/parameters", latched)

    def spin_until(cond, timeout):
        end = time.monotonic() + timeout
        while not cond() and time.monotonic() < end:
            rclpy.spin_once(node, timeout_sec=0.05)
        if not cond():
            raise RuntimeError("the ROS graph did not answer in time")

    try:
        spin_until(lambda: pub.get_subscription_count() > 0 and resets, 60)
        msg = gait_to_msg(gait)
        msg.header.stamp.sec = 4242
        pub.publish(msg)
        spin_until(lambda: active and active[-1].stamp.sec == 4242, 30)
        client = node.create_client(Trigger, "sim_node/reset")
        client.wait_for_service(timeout_sec=10)
        before = resets[-1].stamp
        future = client.call_async(Trigger.Request())
        spin_until(lambda: future.done() and resets[-1].stamp != before, 10)
        t0 = resets[-1].stamp.sec * 10**9 + resets[-1].stamp.nanosec
        ns = lambda o: o.header.stamp.sec * 10**9 + o.header.stamp.nanosec  # noqa: E731
        spin_until(lambda: odom and ns(odom[-1]) >= t0 + 5 * 10**9, 60)
        # the last message stamped t0 is the pose after the reset (a scheduled one may precede it)
        first = [o for o in odom if ns(o) == t0][-1]
        last = next(o for o in odom if abs(ns(o) - (t0 + 5 * 10**9)) < 1000)
        dx = last.pose.pose.position.x - first.pose.pose.position.x
        dy = last.pose.pose.position.y - first.pose.pose.position.y
        return (dx * math.cos(gait.crab_angle) + dy * math.sin(gait.crab_angle)) / 5.0
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
        for p in procs:
            p.send_signal(signal.SIGINT)
        for p in procs:
            try:
                p.wait(10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


def main() -> int:
    from hexapod_description import load_model, summary
    from hexapod_gait import PRESETS, build_joint_table, preset, stance_mask
    from hexapod_gait.footfall import plot_footfall, swing_groups
    from hexapod_sim import HexapodSimulator, evaluate_gait
    from hexapod_sim.fidelity import fidelity_rows, markdown

    out = WS / "out" / "demo"
    out.mkdir(parents=True, exist_ok=True)
    section("hexapod model (hexapod_description)")
    print(summary(load_model()))

    section("gait controller (hexapod_gait)")
    for name in PRESETS:
        gait = preset(name)
        t0 = time.perf_counter()
        table = build_joint_table(gait)
        ms = (time.perf_counter() - t0) * 1e3
        times = np.arange(3 * len(table)) / table.rate
        groups = " -> ".join("{" + ",".join(map(str, sorted(g))) + "}" for g in swing_groups(stance_mask(gait, times)))
        png = plot_footfall(stance_mask(gait, times), times, out / f"footfall_{name}.png", title=name)
        print(f"{name:9s} v={gait.body_velocity:.3f} m/s duty={gait.duty_factor[0]:.3f} table {table.positions.shape} "
              f"in {ms:.2f} ms; swing order {groups}; {png.relative_to(WS)}")

    section("simulator (hexapod_sim): simulated speeds, failure scenarios S0-S4")
    t0 = time.perf_counter()
    with HexapodSimulator() as sim:
        print(markdown(fidelity_rows(sim)))
        library_speed = evaluate_gait(preset("wave"), sim, collisions_fatal=False).speed
    print(f"({time.perf_counter() - t0:.1f} s)")

    section("ROS graph: gait_node + sim_node, one trial of the wave gait")
    t0 = time.perf_counter()
    speed = graph_trial(preset("wave"))
    print(f"through the graph: {speed:.4f} m/s; library evaluation: {library_speed:.4f} m/s "
          f"({'identical' if speed == library_speed else f'differ by {abs(speed - library_speed):.2e}'}); "
          f"{time.perf_counter() - t0:.1f} s")
    print("\nNext: `python scripts/launch.py sim` starts the simulated robot; "
          "`python scripts/launch.py emulated-robot` the radio bridge against the emulated robot.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
