# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Conversions between hexapod_gait values and ROS messages.

Imports message types only, not rclpy, so it is usable from any node and from tests.
"""

from __future__ import annotations

from builtin_interfaces.msg import Duration
from hexapod_gait.parameters import GaitParameters
from hexapod_gait.trajectory import JointTable
from hexapod_msgs.msg import GaitParameters as GaitParametersMsg
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint


def gait_from_msg(msg: GaitParametersMsg) -> GaitParameters:
    """Return the validated gait of a message; GaitParameterError names the bad field."""
    return GaitParameters(
        body_velocity=msg.body_velocity,
        body_height=msg.body_height,
        period=msg.period,
        crab_angle=msg.crab_angle,
        turn_rate=msg.turn_rate,
        radius=list(msg.radius),
        angle_offset=list(msg.angle_offset),
        step_height=list(msg.step_height),
        duty_factor=list(msg.duty_factor),
        phase_offset=list(msg.phase_offset),
        archive_index=msg.archive_index,
    )


def gait_to_msg(gait: GaitParameters, msg: GaitParametersMsg | None = None) -> GaitParametersMsg:
    """Return a hexapod_msgs/GaitParameters message of a gait."""
    out = msg if msg is not None else GaitParametersMsg()
    out.body_velocity = gait.body_velocity
    out.body_height = gait.body_height
    out.period = gait.period
    out.crab_angle = gait.crab_angle
    out.turn_rate = gait.turn_rate
    out.radius = gait.radius.tolist()
    out.angle_offset = gait.angle_offset.tolist()
    out.step_height = gait.step_height.tolist()
    out.duty_factor = gait.duty_factor.tolist()
    out.phase_offset = gait.phase_offset.tolist()
    out.archive_index = gait.archive_index
    return out


def table_to_trajectory(
    table: JointTable, joint_names: tuple[str, ...] | list[str]
) -> JointTrajectory:
    """One gait cycle as a JointTrajectory (positions, velocities, time_from_start)."""
    msg = JointTrajectory()
    msg.joint_names = list(joint_names)
    points = []
    for k, (pos, vel) in enumerate(zip(table.positions.tolist(), table.velocities.tolist())):
        ns = int(round(k * 1e9 / table.rate))
        points.append(
            JointTrajectoryPoint(
                positions=pos,
                velocities=vel,
                time_from_start=Duration(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000),
            )
        )
    msg.points = points
    return msg
