# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""bridge_node's parameters (the station's settings, then the node's own) and status levels."""

from __future__ import annotations

from dataclasses import fields

from diagnostic_msgs.msg import DiagnosticStatus
from hexapod_bridge.reports import Severity
from hexapod_bridge.station import StationConfig
from hexapod_util.ros_glue import ParamSpec

#: joint_states rate [Hz] (commanded angles).
JOINT_STATES_HZ = 30.0
#: HELLOs a start-up servo check sends, a second apart, before it gives up (the robot silent).
SERVO_CHECK_TRIES = 30
#: bridge/status's level of each report's severity.
LEVELS = {
    Severity.OK: DiagnosticStatus.OK,
    Severity.WARN: DiagnosticStatus.WARN,
    Severity.ERROR: DiagnosticStatus.ERROR,
}
#: The station's settings (StationConfig's fields), then the node's own.
PARAMETERS = tuple(
    ParamSpec(
        f.name,
        list(f.default) if isinstance(f.default, tuple) else f.default,
        f.metadata['description'],
        read_only=f.metadata['read_only'],
        range=f.metadata['range'],
    )
    for f in fields(StationConfig)
) + (
    ParamSpec('odom_frame', 'odom', 'REP 105 odometry frame', read_only=True),
    ParamSpec('base_frame', 'base_link', 'Robot base frame', read_only=True),
    ParamSpec('imu_frame', 'imu_link', 'IMU frame', read_only=True),
    ParamSpec(
        'status_rate', 5.0, 'LinkStatus publish rate [Hz]', read_only=True, range=(0.1, 100.0)
    ),
    ParamSpec(
        'autostart',
        True,
        'Configure at start-up, retrying while the port cannot be opened (false: a lifecycle'
        ' manager drives the node); arm_on_start then activates it',
        read_only=True,
    ),
)
