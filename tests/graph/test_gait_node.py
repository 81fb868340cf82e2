# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""gait_node as a separate process: parameters in, one 18-joint cycle out; bad input rejected."""

from __future__ import annotations

import math

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from hexapod_gait import build_joint_table, preset
from hexapod_gait.ros_conversions import gait_to_msg
from hexapod_msgs.msg import GaitParameters as GaitParametersMsg
import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from trajectory_msgs.msg import JointTrajectory

from conftest import status_log_qos, wait_for

LATCHED = QoSProfile(
    depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE
)
JOINTS = [f'joint_{leg}_{k}' for leg in range(1, 7) for k in (1, 2, 3)]

pytestmark = pytest.mark.ros


def test_publishes_cycles_and_rejects_bad_gaits(ros, launch):
    node = launch('hexapod_gait', 'gait_node', params={'initial_preset': 'tripod'})
    trajectories = ros.collect(JointTrajectory, 'gait/joint_trajectory', LATCHED)
    statuses = ros.collect(DiagnosticStatus, 'gait/status', status_log_qos())
    diagnostics = ros.collect(DiagnosticArray, '/diagnostics', 50)
    pub = ros.node.create_publisher(GaitParametersMsg, 'gait/parameters', LATCHED)

    # late joiner gets the latched initial preset
    wait_for(lambda: trajectories, 30, 'initial trajectory')
    first = trajectories[-1]
    assert first.joint_names == JOINTS and len(first.points) == 240
    assert first.points[1].time_from_start.nanosec == pytest.approx(1e9 / 240, abs=1)
    expected = build_joint_table(preset('tripod'))
    assert list(first.points[17].positions) == pytest.approx(
        expected.positions[17].tolist(), abs=1e-12
    )
    assert list(first.points[17].velocities) == pytest.approx(
        expected.velocities[17].tolist(), abs=1e-12
    )

    # a valid gait from another process -> a new cycle whose stamp echoes the request
    wave = gait_to_msg(preset('wave').replace(archive_index=42))
    wave.header.stamp.sec, wave.header.stamp.nanosec = 1234, 5678
    wait_for(lambda: pub.get_subscription_count() > 0, 20, 'gait_node subscription')
    pub.publish(wave)
    wait_for(lambda: trajectories[-1].header.stamp.sec == 1234, 20, 'wave trajectory')
    assert trajectories[-1].header.stamp.nanosec == 5678
    assert list(trajectories[-1].points[0].positions) == pytest.approx(
        build_joint_table(preset('wave')).positions[0].tolist(), abs=1e-12
    )
    n_good = len(trajectories)

    # invalid (NaN velocity) and unreachable (radius too large) gaits: rejected with the reason
    bad = gait_to_msg(preset('tripod'))
    bad.body_velocity = math.nan
    pub.publish(bad)
    wait_for(
        lambda: statuses and statuses[-1].level == DiagnosticStatus.ERROR, 20, 'rejection status'
    )
    assert (
        'body_velocity' in statuses[-1].message
        and 'previous trajectory kept' in statuses[-1].message
    )
    far = gait_to_msg(preset('tripod').replace(radius=[0.29] * 6, archive_index=7))
    pub.publish(far)
    wait_for(
        lambda: 'cannot follow its foot path' in statuses[-1].message, 20, 'unreachable status'
    )
    assert 'leg ' in statuses[-1].message
    assert len(trajectories) == n_good, 'a rejected gait must not replace the trajectory'
    # the same on /diagnostics: gait_node's gait is in ERROR, with the reason
    wait_for(
        lambda: any(
            st.name == 'gait_node: gait' and st.level == DiagnosticStatus.ERROR
            and 'cannot follow its foot path' in st.message
            for a in diagnostics for st in a.status
        ),
        5,
        'the rejection on /diagnostics',
    )  # fmt: skip
    assert node.alive()

    # still working afterwards
    pub.publish(gait_to_msg(preset('quadruped')))
    wait_for(lambda: len(trajectories) > n_good, 20, 'trajectory after rejections')
    # the OK status travels on its own topic: it may arrive just after the trajectory
    wait_for(lambda: statuses[-1].level == DiagnosticStatus.OK, 20, 'OK status after rejections')


def test_robot_rate_gives_120_points(ros, launch):
    launch('hexapod_gait', 'gait_node', params={'initial_preset': 'wave', 'control_rate': 120.0})
    trajectories = ros.collect(JointTrajectory, 'gait/joint_trajectory', LATCHED)
    wait_for(lambda: trajectories, 30, 'trajectory')
    assert len(trajectories[0].points) == 120


def test_bad_initial_preset_logs_and_keeps_running(ros, launch):
    node = launch('hexapod_gait', 'gait_node', params={'initial_preset': 'gallop'})
    statuses = ros.collect(DiagnosticStatus, 'gait/status', status_log_qos())
    wait_for(lambda: "unknown gait preset 'gallop'" in node.log(), 30, 'error in the log')
    pub = ros.node.create_publisher(GaitParametersMsg, 'gait/parameters', LATCHED)
    pub.publish(gait_to_msg(preset('tripod')))
    wait_for(lambda: statuses and statuses[-1].level == DiagnosticStatus.OK, 30, 'gait accepted')
    assert node.alive()
