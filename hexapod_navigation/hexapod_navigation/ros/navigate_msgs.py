# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The navigator's ROS glue: conversions to and from messages, and the bodies' graph port."""

from __future__ import annotations

import math
import time

from builtin_interfaces.msg import Duration, Time
from geometry_msgs.msg import PoseStamped
from hexapod_adapt.ros import GraphPort, stamp_ns
from hexapod_gait import GaitParameters
from hexapod_gait.ros_conversions import gait_to_msg
from hexapod_msgs.action import Navigate
from hexapod_msgs.msg import RobotTrial
from hexapod_navigation.core.episode import Feedback, NavigationResult, Outcome
from hexapod_navigation.core.geometry import Pose2D
from hexapod_navigation.ros.bodies import PoseSample, StepResult
from hexapod_sim.simulator import quat_to_euler
from hexapod_util.ros_glue import ACTION_QOS
from nav_msgs.msg import Odometry
from rclpy.action import ActionClient
from rclpy.callback_groups import CallbackGroup
from rclpy.client import Client
from rclpy.node import Node
from visualization_msgs.msg import Marker


def navigate_client(
    node: Node, action: str = 'navigate', callback_group: CallbackGroup | None = None
) -> ActionClient:
    """
    Return an action client for ``navigate`` whose services keep a burst of answers.

    Its services keep up to ACTION_SERVICES's depth of answers.

    Any Navigate client works; one with the services' default depth loses answers when many goals
    end at once (a goal storm).
    """
    return ActionClient(node, Navigate, action, callback_group=callback_group, **ACTION_QOS)


#: Navigate.Result's outcome constant of each library outcome.
OUTCOME_CODES = {
    Outcome.REACHED: Navigate.Result.REACHED,
    Outcome.TIME_LIMIT: Navigate.Result.TIME_LIMIT,
    Outcome.LEFT_ARENA: Navigate.Result.LEFT_ARENA,
    Outcome.CANCELED: Navigate.Result.CANCELED,
    Outcome.FAILED: Navigate.Result.FAILED,
}


#: The frames a goal's pose may name: the odometry frame, or none (meaning it).
GOAL_FRAMES = ('', 'odom')


def goal_position(goal: Navigate.Goal) -> tuple[float, float, str]:
    """Return the goal's position in odom and '' (or NaN, NaN and why its frame is refused)."""
    frame = goal.pose.header.frame_id
    if frame not in GOAL_FRAMES:
        nan = float('nan')
        return nan, nan, f"goal in frame '{frame}': navigate_node takes goals in odom only"
    position = goal.pose.pose.position
    return float(position.x), float(position.y), ''


def goal_at(x: float, y: float, **fields) -> Navigate.Goal:
    """Return a Navigate goal at (x, y) in odom (``fields``: tolerance, time_limit)."""
    goal = Navigate.Goal(**fields)
    goal.pose.header.frame_id = 'odom'
    goal.pose.pose.position.x, goal.pose.pose.position.y = float(x), float(y)
    goal.pose.pose.orientation.w = 1.0
    return goal


def pose_msg(pose: Pose2D, stamp: Time, frame: str = 'odom') -> PoseStamped:
    """Return a planar pose as a PoseStamped in ``frame``."""
    msg = PoseStamped()
    msg.header.stamp, msg.header.frame_id = stamp, frame
    msg.pose.position.x, msg.pose.position.y = pose.x, pose.y
    msg.pose.orientation.z = math.sin(pose.yaw / 2.0)
    msg.pose.orientation.w = math.cos(pose.yaw / 2.0)
    return msg


def pose_sample(msg: Odometry | PoseStamped) -> PoseSample:
    """Return a pose message (Odometry or PoseStamped) as the navigator's pose sample."""
    pose = msg.pose.pose if isinstance(msg, Odometry) else msg.pose
    p, q = pose.position, pose.orientation
    roll, pitch, yaw = quat_to_euler((q.x, q.y, q.z, q.w))
    return PoseSample(
        stamp_ns(msg.header.stamp), Pose2D(p.x, p.y, yaw), time.monotonic(), roll, pitch
    )


def step_result(msg: RobotTrial) -> StepResult:
    """Return bridge_node's trial result as a robot step reads it."""
    return StepResult(msg.valid, msg.reason, Pose2D(msg.x, msg.y, msg.yaw), time.monotonic())


def goal_marker(x: float, y: float, tolerance: float, stamp: Time) -> Marker:
    """Return the goal circle (a flat cylinder of the tolerance's radius) in ``odom``."""
    m = Marker(ns='navigate', id=0, type=Marker.CYLINDER, action=Marker.ADD)
    m.header.frame_id, m.header.stamp = 'odom', stamp
    m.pose.position.x, m.pose.position.y, m.pose.orientation.w = x, y, 1.0
    m.scale.x = m.scale.y = 2.0 * tolerance
    m.scale.z = 0.02
    m.color.r, m.color.g, m.color.a = 0.1, 0.8, 0.6
    return m


def duration_msg(seconds: float) -> Duration:
    """Return ``seconds`` as a builtin_interfaces/Duration."""
    ns = int(seconds * 1e9)
    return Duration(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)


def feedback_msg(f: Feedback, stamp: Time) -> Navigate.Feedback:
    """Return the action's feedback after a step."""
    msg = Navigate.Feedback(distance_remaining=f.distance_left, steps=f.steps)
    msg.current_pose = pose_msg(f.pose, stamp)
    msg.prediction_error = f.prediction_error
    msg.navigation_time = duration_msg(f.walking_time)
    return msg


def result_msg(
    result: NavigationResult, goal: tuple[float, float], recording: str, stamp: Time
) -> Navigate.Result:
    """Return the action's result of an episode that ran (``recording``: its MCAP file or '')."""
    out = Navigate.Result(recording=recording)
    out.reached, out.reason = result.reached, result.reason
    out.outcome = OUTCOME_CODES[result.outcome]
    out.walking_time, out.path_length, out.steps = (
        result.walking_time,
        result.path_length,
        result.steps,
    )
    out.distance_left = result.end.distance_to(*goal)
    out.final_pose = pose_msg(result.end, stamp)
    return out


def ending(
    result: NavigationResult | None,
    reason: str,
    goal: tuple[float, float],
    recording: str,
    stamp: Time,
    preempted: bool,
    cancel_requested: bool,
) -> tuple[str, Navigate.Result]:
    """
    Return how a walked goal ends: the goal handle's call and the result.

    The call is 'succeed', 'canceled' or 'abort'. ``result`` None: the graph stopped answering,
    and ``reason`` says how.
    """
    if result is None:
        failed = Navigate.Result(outcome=Navigate.Result.FAILED, reason=reason)
        failed.recording = recording
        return 'abort', failed
    out = result_msg(result, goal, recording, stamp)
    if result.outcome is Outcome.CANCELED and preempted and not cancel_requested:
        out.outcome, out.reason = Navigate.Result.PREEMPTED, 'preempted by a newer goal'
        return 'abort', out
    if result.outcome is Outcome.CANCELED:
        return 'canceled', out
    return ('succeed' if result.reached else 'abort'), out


def unwalked(closing: bool, cancel_requested: bool) -> tuple[str, Navigate.Result]:
    """Return how a goal that never got its turn ends: cancelled, superseded, or closing."""
    if closing:
        return 'abort', Navigate.Result(outcome=Navigate.Result.FAILED, reason='shutting down')
    if cancel_requested:
        return 'canceled', Navigate.Result(outcome=Navigate.Result.CANCELED, reason='canceled')
    return 'abort', Navigate.Result(
        outcome=Navigate.Result.PREEMPTED, reason='preempted by a newer goal before it started'
    )


class GraphNavigationPort:
    """The bodies' :class:`~hexapod_navigation.ros.bodies.NavigationPort` over a GraphPort."""

    def __init__(self, port: GraphPort, stop_client: Client) -> None:
        self.port, self.stop_client = port, stop_client

    def publish_gait(self, gait: GaitParameters) -> int:
        """Publish a gait with a unique stamp; return the stamp [ns]."""
        msg = gait_to_msg(gait)
        stamp = self.port.stamp(msg)
        self.port.publish(msg)
        return stamp

    def active_stamp(self) -> int | None:
        """Return the stamp of the gait sim_node plays."""
        return self.port.active_stamp()

    def activated_at(self, stamp: int) -> int | None:
        """Return the simulation time [ns] the gait stamped ``stamp`` took effect."""
        return self.port.activated_at(stamp)

    def upload(self, gait: GaitParameters, timeout: float) -> tuple[bool, str]:
        """Upload through bridge_node."""
        answer = self.port.upload_msg(gait_to_msg(gait), timeout)
        return answer.success, answer.message

    def start_trial(self) -> tuple[bool, str]:
        """Start a trial on the robot."""
        return self.port.start_trial()

    def stop_trial(self) -> tuple[bool, str]:
        """Stop the robot's trial."""
        answer = self.port.call(self.stop_client, 'stop the trial', timeout=2.0)
        return answer.success, answer.message
