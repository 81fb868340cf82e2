# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The robot's health as /diagnostics shows it (hexapod_bridge.health), without ROS."""

from hexapod_bridge.health import imu_health, link_health, servo_health, urdf_joint
from hexapod_bridge.station import LinkSnapshot
from hexapod_util.health import ERROR, Health, OK, WARN
import pytest

MIRRORED = (1, 6, 5, 4, 3, 2)  # the robot's leg 2 is URDF leg 6


def _snap(connected=True, heard=0.1, ok=90, bad=10) -> LinkSnapshot:
    return LinkSnapshot(connected, True, heard, ok, bad, 0, 0, 0, 0, '' if connected else 'gone')


def test_servos_are_named_by_their_urdf_joint_through_the_leg_map():
    assert urdf_joint(2, (1, 2, 3, 4, 5, 6)) == 'joint_1_1'  # leg 1's coxa
    assert urdf_joint(5, MIRRORED) == 'joint_6_1'  # robot leg 2's coxa
    assert urdf_joint(19, MIRRORED) == 'joint_2_3'  # robot leg 6's tibia
    with pytest.raises(ValueError, match='no servo 40'):
        urdf_joint(40, MIRRORED)


def test_every_servo_has_a_status_and_a_reported_one_is_an_error():
    statuses = servo_health({5: 10.0}, MIRRORED, now=12.5)
    assert len(statuses) == 18
    dead = [s for s in statuses if s.level == ERROR]
    assert [s.name for s in dead] == ['joint_6_1 (servo 5)']
    assert dead[0].values['reported_s_ago'] == '2.5'
    assert all(s.level == OK for s in statuses if s not in dead)


def test_the_link_is_ok_when_heard_warn_when_silent_and_error_when_down():
    up = link_health(_snap(), '/dev/ttyUSB0')
    assert (up.level, up.values['quality']) == (OK, '0.900')
    assert link_health(_snap(heard=5.0), 'p').level == WARN
    down = link_health(_snap(connected=False), 'p')
    assert down.level == ERROR and 'gone' in down.message


def test_noise_on_the_radio_turns_the_link_warn_with_its_counts():
    from dataclasses import replace

    noisy = replace(
        _snap(), bad_frame_rate=4.4, last_error='4.4 bad frames/s over the last 10 s (...)'
    )
    health = link_health(noisy, '/dev/ttyUSB0')
    assert health.level == WARN and 'bad frames/s' in health.message
    assert health.values['bad_frames_per_s'] == '4.40'
    assert link_health(replace(_snap(), bad_frame_rate=0.4), '/dev/ttyUSB0').level == OK


def test_the_imu_is_ok_while_it_streams():
    assert imu_health(None, 10.0, 'imu').level == WARN
    assert imu_health(9.5, 10.0, 'imu').level == OK
    assert imu_health(5.0, 10.0, 'imu').level == ERROR


def test_a_status_level_outside_the_four_is_refused():
    with pytest.raises(ValueError, match='level'):
        Health('x', 7, 'm', 'hw')
