# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""sim_node's messages built from the simulator's state (no rclpy: message types only)."""

from __future__ import annotations

from typing import Sequence

from builtin_interfaces.msg import Time
from hexapod_msgs.msg import FootContacts, LegDamage
from hexapod_sim.damage import Damage
from hexapod_sim.simulator import Simulator
from hexapod_sim.trajectory_input import cycle_from_points, CycleTable, MAX_POINTS, TrajectoryError
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, JointState
from std_msgs.msg import Header
from trajectory_msgs.msg import JointTrajectory


def stamp(seconds: float) -> Time:
    """Return a simulation time [s] as a builtin_interfaces/Time."""
    ns = int(round(seconds * 1e9))
    return Time(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)


def odometry(sim: Simulator, when: Time, odom_frame: str, base_frame: str) -> Odometry:
    """Return the base's pose in ``odom_frame`` and its twist in ``base_frame`` (REP 105)."""
    pos, quat = sim.base_pose()
    lin_b, ang_b = sim.base_twist_body()
    odom = Odometry()
    odom.header.stamp, odom.header.frame_id, odom.child_frame_id = when, odom_frame, base_frame
    o = odom.pose.pose
    o.position.x, o.position.y, o.position.z = (float(v) for v in pos)
    o.orientation.x, o.orientation.y, o.orientation.z, o.orientation.w = (float(v) for v in quat)
    t = odom.twist.twist  # REP: twist is expressed in the child frame
    t.linear.x, t.linear.y, t.linear.z = (float(v) for v in lin_b)
    t.angular.x, t.angular.y, t.angular.z = (float(v) for v in ang_b)
    return odom


def joint_state(sim: Simulator, when: Time, base_frame: str) -> JointState:
    """Return the joints' positions, velocities and efforts."""
    q, qd, effort = sim.joint_states()
    return JointState(
        header=Header(stamp=when, frame_id=base_frame),
        name=list(sim.model.joint_names),
        position=q.tolist(),
        velocity=qd.tolist(),
        effort=effort.tolist(),
    )


def imu(sim: Simulator, when: Time, base_frame: str) -> Imu:
    """Return the simulated IMU's orientation, rates and accelerations."""
    iq, iw, ia = sim.imu()
    msg = Imu(header=Header(stamp=when, frame_id=base_frame))
    o, w, a = msg.orientation, msg.angular_velocity, msg.linear_acceleration
    o.x, o.y, o.z, o.w = (float(v) for v in iq)
    w.x, w.y, w.z = (float(v) for v in iw)
    a.x, a.y, a.z = (float(v) for v in ia)
    return msg


def foot_contacts(sim: Simulator, when: Time, base_frame: str) -> FootContacts:
    """Return which feet touch the ground."""
    return FootContacts(
        header=Header(stamp=when, frame_id=base_frame),
        in_contact=[bool(c) for c in sim.report.contacts],
    )


def damage_msg(damage: Damage, when: Time) -> LegDamage:
    """Return ``damage`` as sim/damage says it."""
    legs, kinds, strengths, joints = damage.as_lists()
    return LegDamage(
        header=Header(stamp=when),
        failed_legs=legs,
        kinds=kinds,
        strengths=strengths,
        joints=joints,
        label=damage.label,
    )


def cycle_from_msg(msg: JointTrajectory, joint_names: Sequence[str], dt: float) -> CycleTable:
    """
    Return one gait cycle of a JointTrajectory, resampled to the step ``dt``.

    TrajectoryError says what is wrong; an over-long message is refused before anything is copied
    out of it.
    """
    if len(msg.points) > MAX_POINTS:
        raise TrajectoryError(
            f'a gait cycle may have at most {MAX_POINTS} points, got {len(msg.points)}'
        )
    return cycle_from_points(
        msg.joint_names,
        [pt.time_from_start.sec + pt.time_from_start.nanosec * 1e-9 for pt in msg.points],
        [list(pt.positions) for pt in msg.points],
        [list(pt.velocities) for pt in msg.points],
        joint_names,
        dt,
    )
