# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""bridge_node's messages from what the station hears (no rclpy: message types only)."""

from __future__ import annotations

import math

from builtin_interfaces.msg import Time
from hexapod_bridge.odometry import ChainedPose, SPEED_ACCURACY
from hexapod_bridge.station import RETRYABLE_FAULTS, TrialResult
from hexapod_description.tf_tree import quat_from_rpy
from hexapod_msgs.msg import LinkStatus, RobotTrial
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu


def _planar_odometry(
    x: float, y: float, yaw: float, stamp: Time, odom_frame: str, base_frame: str
) -> Odometry:
    """Return an Odometry at (x, y) turned ``yaw`` about z, twist and covariances zero."""
    odom = Odometry()
    odom.header.stamp, odom.header.frame_id, odom.child_frame_id = stamp, odom_frame, base_frame
    odom.pose.pose.position.x, odom.pose.pose.position.y = x, y
    odom.pose.pose.orientation.z = math.sin(yaw / 2.0)
    odom.pose.pose.orientation.w = math.cos(yaw / 2.0)
    return odom


def trial_odometry(r: TrialResult, stamp: Time, odom_frame: str, base_frame: str) -> Odometry:
    """
    Return a trial's odometry (``trial_odom``): its displacement, in the frame it started in.

    The orientation is the heading change over the trial (the IMU's yaw); the pose covers the
    whole walk, settling included, and the twist is the mean velocity over the timed part (a
    trial's speed); covariances are the estimate's stated accuracy.
    """
    odom = _planar_odometry(r.x, r.y, r.yaw, stamp, odom_frame, base_frame)
    odom.twist.twist.linear.x, odom.twist.twist.linear.y = r.vx, r.vy
    walked = max(r.walk, r.duration)
    odom.pose.covariance[0] = odom.pose.covariance[7] = (SPEED_ACCURACY * walked) ** 2
    odom.twist.covariance[0] = odom.twist.covariance[7] = SPEED_ACCURACY**2
    return odom


def robot_trial(r: TrialResult, stamp: Time, odom_frame: str) -> RobotTrial:
    """Return a trial's ``trial_result``: its validity, the reason, and the estimate if any."""
    msg = RobotTrial(fault=int(r.fault), valid=r.valid, retryable=r.fault in RETRYABLE_FAULTS)
    msg.header.stamp, msg.header.frame_id = stamp, odom_frame
    msg.reason, msg.robot_state = r.problem, r.state
    msg.duration, msg.walk = float(r.duration), float(max(r.walk, r.duration))
    if r.estimate is not None:
        msg.has_estimate = True
        msg.distance, msg.speed = float(r.estimate.distance), float(r.estimate.speed)
        msg.x, msg.y, msg.yaw, msg.vx, msg.vy = (float(v) for v in (r.x, r.y, r.yaw, r.vx, r.vy))
    return msg


#: The twist variance of ``odom`` while a trial walks [m^2/s^2]: unknown until the trial ends.
UNKNOWN_TWIST_VARIANCE = 1.0e6


def continuous_odometry(
    pose: ChainedPose, walking: bool, stamp: Time, odom_frame: str, base_frame: str
) -> Odometry:
    """
    Return ``odom``: the chained pose (:class:`ChainedPose`), published continuously.

    The twist is zero: true while the robot stands; while a trial walks, its velocity is known at
    its end only (``trial_odom``), so the covariance says unknown (UNKNOWN_TWIST_VARIANCE).
    """
    odom = _planar_odometry(pose.x, pose.y, pose.yaw, stamp, odom_frame, base_frame)
    odom.pose.covariance[0] = odom.pose.covariance[7] = pose.variance
    twist_variance = UNKNOWN_TWIST_VARIANCE if walking else SPEED_ACCURACY**2
    odom.twist.covariance[0] = odom.twist.covariance[7] = twist_variance
    return odom


def xsens_imu(m, stamp: Time, frame: str) -> Imu:
    """Return an Xsens measurement (euler [deg], gyr, acc) as sensor_msgs/Imu."""
    msg = Imu()
    msg.header.stamp, msg.header.frame_id = stamp, frame
    q = quat_from_rpy(*(math.radians(v) for v in m.euler))
    msg.orientation.x, msg.orientation.y, msg.orientation.z, msg.orientation.w = q
    av, la = msg.angular_velocity, msg.linear_acceleration
    av.x, av.y, av.z = (float(v) for v in m.gyr)
    la.x, la.y, la.z = (float(v) for v in m.acc)
    return msg


def attitude_imu(t, stamp: Time, frame: str) -> Imu:
    """Return the robot's attitude telemetry (roll, pitch, yaw [rad]) as an orientation Imu."""
    msg = Imu()
    msg.header.stamp, msg.header.frame_id = stamp, frame
    q = quat_from_rpy(t.roll, t.pitch, t.yaw)
    msg.orientation.x, msg.orientation.y, msg.orientation.z, msg.orientation.w = q
    msg.angular_velocity_covariance[0] = -1.0  # not provided by the telemetry
    msg.linear_acceleration_covariance[0] = -1.0
    return msg


def reports_down_since(status: LinkStatus, wall_time: float) -> bool:
    """Return True if ``status`` says "not connected" and was stamped after ``wall_time`` [s]."""
    stamp = status.header.stamp.sec + status.header.stamp.nanosec * 1e-9
    return not status.connected and stamp > wall_time
