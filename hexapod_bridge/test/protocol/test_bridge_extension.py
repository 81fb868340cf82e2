# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Gait-upload extension frames (protocol.extension): layout, round trips, leg map."""

from __future__ import annotations

import math
import struct

from hexapod_bridge.protocol import extension as ext
from hexapod_gait import preset
import pytest


def test_extension_round_trip_and_layout():
    frame = ext.encode_command(ext.Cmd.SET_PARAM, 300, bytes([5]) + struct.pack('<f', 0.15))
    assert len(frame) == 10 and frame[0] == 0xE7 and frame[1] == 0x10 and frame[2] == 300 & 0xFF
    decoded = ext.decode_command(frame)
    assert decoded.payload[0] == 5 and struct.unpack('<f', decoded.payload[1:5])[
        0
    ] == pytest.approx(0.15)
    corrupted = bytearray(frame)
    corrupted[5] ^= 0x40
    with pytest.raises(ext.ExtensionError, match='CRC'):
        ext.decode_command(bytes(corrupted))
    report = ext.encode_report(ext.Report.TRIAL, 4, bytes([1, 0, 0x13, 0x88]))
    assert ext.decode_report(report).payload == bytes([1, 0, 0x13, 0x88])


def test_upload_frames_and_values_round_trip():
    gait = preset('wave').replace(archive_index=1234)
    values = ext.gait_values(gait)
    frames = ext.upload_frames(values, gait_id=7, first_seq=250)
    assert len(frames) == ext.N_PARAMS + 1 == 37
    assert [f[2] for f in frames[:7]] == [250, 251, 252, 253, 254, 255, 0]
    commit = ext.decode_command(frames[-1])
    assert commit.type == ext.Cmd.COMMIT and commit.payload[0] == 36
    assert struct.unpack('>H', commit.payload[1:3])[0] == ext.values_crc(ext.quantise(values))
    back = ext.gait_from_values(ext.quantise(values))
    assert back.archive_index == 1234
    assert back.duty_factor[0] == pytest.approx(5 / 6, abs=1e-6)


@pytest.mark.parametrize('crab', [math.pi, -math.pi])
def test_a_value_on_a_bound_without_a_float32_is_sent_just_inside_it(crab):
    # float32(pi) > pi: sent as is, the robot would refuse the omni gaits that walk straight back
    gait = preset('tripod').replace(crab_angle=crab, turn_rate=0.2)
    values = ext.gait_values(gait)
    assert abs(values[3]) <= math.pi and values[3] == pytest.approx(crab, abs=1e-6)
    robot = ext.gait_from_values(ext.quantise(values))
    assert robot.crab_angle == values[3] and robot.turn_rate == pytest.approx(0.2)
