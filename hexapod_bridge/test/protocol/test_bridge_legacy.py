# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The legacy radio frames (hexapod_bridge.protocol.legacy): layout, checksums, refusals."""

from __future__ import annotations

import struct

from hexapod_bridge.protocol import legacy
import pytest


def test_movement_frame_bytes_and_checksum():
    frame = legacy.encode_movement(
        legacy.Movement(direction=1, twist=0.0, speed=0.3, height_mm=140.0, function=0)
    )
    assert frame == bytes(
        [0x01, 1, 100, 0x02, 30, 0x03, 50, 0x04, 0, (1 + 1 + 100 + 2 + 30 + 3 + 50 + 4) & 0xFF]
    )
    m = legacy.decode_movement(frame)
    assert (m.direction, m.speed, m.height_mm, m.function) == (1, 0.3, 140.0, 0)
    assert m.twist == pytest.approx(0.0)
    reset = legacy.encode_movement(legacy.Movement(function=legacy.Function.RESET))
    assert reset[8] == 55 and len(reset) == 10


@pytest.mark.parametrize(
    'movement,match',
    [
        (legacy.Movement(direction=9), 'direction code'),
        (legacy.Movement(height_mm=300), 'height'),
        (legacy.Movement(height_mm=20), 'height'),
        (legacy.Movement(speed=3.0), 'speed does not fit'),
    ],
)
def test_movement_encoding_refuses_bad_values(movement, match):
    with pytest.raises(legacy.ProtocolError, match=match):
        legacy.encode_movement(movement)


def test_movement_decoding_refuses_corruption():
    frame = bytearray(legacy.encode_movement(legacy.Movement()))
    frame[4] ^= 0x01
    with pytest.raises(legacy.ProtocolError, match='checksum'):
        legacy.decode_movement(bytes(frame))


def test_other_pc_to_robot_frames_are_10_bytes_exactly():
    assert legacy.encode_ping() == bytes([0x37]) + bytes(9)
    assert legacy.encode_motor_power(True) == bytes([0xFF, 0xFA, 1]) + bytes(7)
    assert legacy.encode_pid_enable(True, 3) == bytes([0xFF, 0xFB, 1, 3]) + bytes(6)
    assert legacy.encode_pid_gain(1, 2, 0.5) == bytes([0xFF, 0xDE, 1, 2]) + struct.pack(
        '<f', 0.5
    ) + bytes(2)
    assert legacy.encode_imu_period(0.5) == bytes([0xFF, 0xDD]) + struct.pack('<f', 0.5) + bytes(4)
    assert legacy.encode_charging(True) == bytes([0xFF, 0xF8, 0x37, 1]) + bytes(6)
    with pytest.raises(legacy.ProtocolError):
        legacy.encode_pid_enable(True, 4)
    with pytest.raises(legacy.ProtocolError):
        legacy.encode_imu_period(float('nan'))
