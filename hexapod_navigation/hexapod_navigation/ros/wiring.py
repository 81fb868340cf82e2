# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""How navigate_node is wired to the graph: its pose subscriptions and the body it walks."""

from __future__ import annotations

from typing import Any, Mapping

from geometry_msgs.msg import PoseStamped
from hexapod_adapt import SampleLog, Waiter
from hexapod_msgs.msg import RobotTrial
from hexapod_navigation.ros import navigate_msgs as conv
from hexapod_navigation.ros.bodies import PoseLog, RobotGraphBody, SimGraphBody, StepResult
from hexapod_util.ros_glue import POSES, TRIALS
from nav_msgs.msg import Odometry
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
from rclpy.node import Node


def subscribe_poses(
    node: Node, values: Mapping[str, Any], poses: PoseLog, trial_poses: SampleLog[StepResult]
) -> bool:
    """
    Feed ``poses`` from the pose source, and ``trial_poses`` from ``odom`` where that is not it.

    The pose source is ``pose_topic`` when set (a PoseStamped or an Odometry, e.g. motion
    capture), else ``odom`` (sim_node's, or on the robot bridge_node's trials chained); on the
    robot ``trial_result`` (bridge_node's, one per trial, valid or not) goes to ``trial_poses``.
    The newest few poses only (POSES), so a reader that falls behind skips stale poses instead of
    timing steps by them.
    Returns whether the pose source is external.
    """
    sensors = MutuallyExclusiveCallbackGroup()
    external = bool(values['pose_topic'])
    if external:
        kind = PoseStamped if values['pose_type'] == 'pose' else Odometry
        node.create_subscription(
            kind, values['pose_topic'], lambda m: poses.append(conv.pose_sample(m)), POSES,
            callback_group=sensors,
        )  # fmt: skip
    else:
        node.create_subscription(
            Odometry, 'odom', lambda m: poses.append(conv.pose_sample(m)), POSES,
            callback_group=sensors,
        )  # fmt: skip
    if values['mode'] == 'robot':
        node.create_subscription(
            RobotTrial, 'trial_result', lambda m: trial_poses.append(conv.step_result(m)), TRIALS,
            callback_group=sensors,
        )  # fmt: skip
    return external


def make_body(
    values: Mapping[str, Any],
    graph: conv.GraphNavigationPort,
    poses: PoseLog,
    trial_poses: SampleLog[StepResult],
    waiter: Waiter,
    external: bool,
    tip_guard: float,
) -> SimGraphBody | RobotGraphBody:
    """Return the body navigate walks: sim_node's (``mode`` sim) or bridge_node's (robot)."""
    if values['mode'] == 'sim':
        return SimGraphBody(graph, poses, waiter, values['timeout'], tip_guard)
    return RobotGraphBody(
        graph, poses, trial_poses, waiter, values['trial_duration'], external, values['timeout']
    )  # fmt: skip
