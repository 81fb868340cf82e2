# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
What bridge_node says about a trial or a servo report, without ROS.

Each report is a severity, a line and the key-value pairs for bridge/status; the node turns them
into diagnostics and messages.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import enum

from hexapod_bridge.odometry import SPEED_ACCURACY
from hexapod_bridge.servos import SERVO_IDS, servo_place
from hexapod_bridge.station import TrialResult


class Severity(enum.Enum):
    """How bad a report is (DiagnosticStatus's levels)."""

    OK = 'ok'
    WARN = 'warn'
    ERROR = 'error'


@dataclass(frozen=True)
class Report:
    """A line for bridge/status with its severity and values."""

    severity: Severity
    text: str
    values: dict[str, object] = field(default_factory=dict)


def trial_report(r: TrialResult, imu_configured: bool) -> Report:
    """Say how a trial ended: its IMU estimate, or why it cannot be scored."""
    if r.estimate is None and not imu_configured:
        return Report(
            Severity.WARN,
            'trial finished; no IMU configured: enter the measured distance by hand'
            ' (adapt_node in manual mode: report_distance)',
            {'state': r.state},
        )
    if not r.valid:
        return Report(
            Severity.ERROR,
            f'trial not scorable ({r.fault.name}): {r.problem}',
            {'state': r.state, 'fault': r.fault.name},
        )
    est = r.estimate
    return Report(
        Severity.OK,
        f'trial {r.state.lower()}: {est.distance:.3f} m, {est.speed:.3f} m/s '
        f'(IMU estimate, +/-{SPEED_ACCURACY} m/s)',
        {
            'distance': f'{est.distance:.4f}',
            'speed': f'{est.speed:.4f}',
            'samples': est.samples,
            'drift_removed': f'{est.drift_velocity:.3f}',
            'state': r.state,
        },
    )


@dataclass(frozen=True)
class ServoReport:
    """A servo the robot says did not answer its ping, placed on a leg (None: no such servo)."""

    servo: int
    robot_leg: int | None  # the robot's numbering
    leg: int | None  # the thesis's numbering, through the bridge's leg_map
    joint: str | None
    report: Report


def servo_report(servo: int, leg_map: tuple[int, ...] | list[int]) -> ServoReport:
    """Place a dead-servo report through ``leg_map``; a servo the robot lacks is refused."""
    place = servo_place(servo)
    if place is None:  # a corrupted report, or firmware that numbers servos differently
        return ServoReport(
            servo,
            None,
            None,
            None,
            Report(
                Severity.WARN,
                f'robot reports servo {servo} failed its ping, but the robot has no servo'
                f' {servo} (ids {SERVO_IDS[0]}..{SERVO_IDS[-1]}): no leg is marked failed',
            ),
        )
    leg = list(leg_map).index(place.robot_leg) + 1
    return ServoReport(
        servo,
        place.robot_leg,
        leg,
        place.joint,
        Report(
            Severity.ERROR,
            f'servo {servo} ({place.joint} of leg {leg}, robot leg {place.robot_leg}) did not'
            ' answer its ping',
            {'servo': str(servo), 'leg': str(leg)},
        ),
    )
