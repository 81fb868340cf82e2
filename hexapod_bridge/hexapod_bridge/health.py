# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The robot's health as bridge_node sees it: one status per servo, the radio link, the IMU.

ROS-free: bridge_node publishes these on ``/diagnostics`` (:mod:`hexapod_util.diagnostics`).
Servos are named as in the URDF (``joint_<leg>_<1 coxa, 2 femur, 3 tibia>``, through the
configured ``leg_map``); a servo is ERROR once the robot reports it did not answer its ping, and
stays so (the robot does not report recoveries).
"""

from __future__ import annotations

from typing import Mapping, Sequence

from hexapod_bridge.servos import JOINTS, SERVO_IDS, servo_place
from hexapod_bridge.station import BAD_FRAME_RATE, IMU_SILENT_S, LINK_SILENT_S, LinkSnapshot
from hexapod_util.health import ERROR, Health, OK, WARN


def urdf_joint(servo: int, leg_map: Sequence[int]) -> str:
    """Return the URDF name of a servo's joint, through ``leg_map`` (robot leg -> URDF leg)."""
    place = servo_place(servo)
    if place is None:
        raise ValueError(f'the robot has no servo {servo}')
    leg = list(leg_map).index(place.robot_leg) + 1
    return f'joint_{leg}_{JOINTS.index(place.joint) + 1}'


def servo_health(dead: Mapping[int, float], leg_map: Sequence[int], now: float) -> list[Health]:
    """Return one status per servo; ``dead``: servo id -> when its failure was reported."""
    out = []
    for servo in SERVO_IDS:
        name = f'{urdf_joint(servo, leg_map)} (servo {servo})'
        hardware = f'Dynamixel servo id {servo}'
        if servo in dead:
            ago = f'{now - dead[servo]:.1f}'
            out.append(
                Health(name, ERROR, 'did not answer its ping', hardware, {'reported_s_ago': ago})
            )
        else:
            out.append(Health(name, OK, 'no failure reported', hardware))
    return out


def link_health(snap: LinkSnapshot | None, port: str, why_none: str = '') -> Health:
    """
    Return the radio link's status: connected, heard lately, frames and errors.

    ``snap`` None: the node has no link (not configured), for ``why_none``.
    """
    if snap is None:
        return Health('radio link', ERROR, f'no link: {why_none}', f'433 MHz radio on {port}')
    frames = snap.frames_ok + snap.checksum_errors
    quality = snap.frames_ok / frames if frames else 1.0
    values = {
        'port': port,
        'quality': f'{quality:.3f}',
        'frames_ok': str(snap.frames_ok),
        'checksum_errors': str(snap.checksum_errors),
        'bytes_dropped': str(snap.bytes_dropped),
        'retries': str(snap.retries),
        'last_frame_age_s': f'{snap.seconds_since_heard:.2f}',
        'bad_frames_per_s': f'{snap.bad_frame_rate:.2f}',
        'resyncs': str(snap.resyncs),
        'armed': str(snap.armed),
    }
    if not snap.connected:
        level, message = ERROR, f'not connected: {snap.last_error or "port not open"}'
    elif snap.seconds_since_heard > LINK_SILENT_S:
        level, message = WARN, f'connected, robot silent for {snap.seconds_since_heard:.1f} s'
    elif snap.bad_frame_rate > BAD_FRAME_RATE:
        level, message = WARN, f'connected, {snap.last_error}'
    else:
        level, message = OK, 'connected'
    return Health('radio link', level, message, f'433 MHz radio on {port}', values)


def imu_health(last: float | None, now: float, source: str) -> Health:
    """Return the IMU's status from the time of its last message (None: none yet)."""
    if last is None:
        return Health('IMU', WARN, 'no IMU data yet', source)
    age = now - last
    values = {'last_message_age_s': f'{age:.2f}'}
    if age > IMU_SILENT_S:
        return Health('IMU', ERROR, f'silent for {age:.1f} s', source, values)
    return Health('IMU', OK, 'streaming', source, values)
