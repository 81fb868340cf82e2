# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""What bridge_node reports about trials and dead servos, checked without ROS."""

from __future__ import annotations

from hexapod_bridge.odometry import TrialEstimate
from hexapod_bridge.reports import servo_report, Severity, trial_report
from hexapod_bridge.station import TrialFault, TrialResult
import numpy as np
import pytest

IDENTITY = (1, 2, 3, 4, 5, 6)


def test_a_trial_without_an_imu_asks_for_the_tape_measure():
    no_imu = TrialResult('DONE', 5.0, problem='no IMU configured', fault=TrialFault.NO_ESTIMATE)
    report = trial_report(no_imu, imu_configured=False)
    assert report.severity is Severity.WARN and 'enter the measured distance' in report.text


def test_a_trial_whose_estimate_failed_says_why():
    r = TrialResult('DONE', 5.0, problem='too few IMU samples', fault=TrialFault.NO_ESTIMATE)
    report = trial_report(r, True)
    assert report.severity is Severity.ERROR
    assert report.text == 'trial not scorable (NO_ESTIMATE): too few IMU samples'
    assert report.values['fault'] == 'NO_ESTIMATE'


def test_a_spoilt_trial_with_an_estimate_is_reported_unscorable_not_as_a_speed():
    est = TrialEstimate(96.3, 19.26, np.array([96.3, 0.0]), 500, 0.01)
    why = 'the radio port was lost: /dev/ttyUSB0 lost'
    r = TrialResult('NO_REPORT', 5.0, est, problem=why, fault=TrialFault.LINK_LOST)
    report = trial_report(r, True)
    assert report.severity is Severity.ERROR and not r.valid
    assert report.text == f'trial not scorable (LINK_LOST): {why}'
    assert '19.26' not in report.text


def test_a_fault_and_its_reason_come_together():
    with pytest.raises(ValueError, match='reason exactly when it has a fault'):
        TrialResult('DONE', 5.0, fault=TrialFault.LINK_LOST)
    with pytest.raises(ValueError, match='reason exactly when it has a fault'):
        TrialResult('DONE', 5.0, problem='something')


def test_a_trial_with_an_estimate_reports_distance_and_speed():
    est = TrialEstimate(1.2, 0.24, np.array([1.2, 0.0]), 500, 0.01)
    report = trial_report(TrialResult('DONE', 5.0, est), True)
    assert report.severity is Severity.OK
    assert report.text.startswith('trial done: 1.200 m, 0.240 m/s')
    assert report.values['samples'] == 500


def test_a_dead_servo_is_placed_on_its_leg_through_the_leg_map():
    r = servo_report(5, IDENTITY)  # servo 5: robot leg 2's coxa
    assert (r.robot_leg, r.leg, r.joint) == (2, 2, 'coxa')
    assert r.report.severity is Severity.ERROR
    swapped = servo_report(5, (2, 1, 3, 4, 5, 6))  # thesis leg 1 is robot leg 2
    assert swapped.leg == 1


def test_a_servo_the_robot_does_not_have_marks_no_leg():
    r = servo_report(99, IDENTITY)
    assert r.leg is None and r.report.severity is Severity.WARN
    assert 'the robot has no servo 99' in r.report.text
