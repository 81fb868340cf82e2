# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The stream parsers (hexapod_bridge.protocol.stream): host and robot receive paths, resync."""

from __future__ import annotations

import struct

from hexapod_bridge.protocol import extension as ext
from hexapod_bridge.protocol import legacy
from hexapod_bridge.protocol.stream import HostParser, LegacyCommand, PingFrame, RobotReceiver
import pytest


def test_robot_to_pc_frames_parse():
    parser = HostParser()
    t = legacy.Telemetry(12.0, 0.1, -0.2, 1.5, 0.0, 0.05)
    stream = (
        legacy.encode_telemetry(t)
        + bytes([0xFF, 0xFA])
        + legacy.encode_error(11, 7)
        + legacy.encode_text('LOW BATTERY')
        + legacy.encode_charger(1, 11.7)
        + legacy.encode_ack(0x42)
        + ext.encode_report(ext.Report.ACK, 9, bytes([0x10, 0, 0, 3]))
    )
    frames = parser.feed(stream)
    assert [type(f).__name__ for f in frames] == [
        'Telemetry',
        'PingReply',
        'ErrorReport',
        'Text',
        'ChargerStatus',
        'MovementAck',
        'ReportFrame',
    ]
    assert (
        frames[0].yaw == pytest.approx(1.5)
        and frames[2].describe() == 'servo 7 did not answer a ping'
    )
    assert frames[3].text == 'LOW BATTERY' and frames[4].voltage == pytest.approx(11.7)
    assert frames[5].checksum == 0x42 and frames[6].seq == 9
    assert parser.stats.frames_ok == 7 and parser.stats.bytes_dropped == 0
    assert legacy.ErrorReport(1, 0x05).describe() == 'servo bus error: parity, framing'


def test_host_parser_rejects_implausible_and_resyncs():
    parser = HostParser()
    bad_telemetry = bytes([0xFF, 0xFE]) + struct.pack('<6f', 1.0, float('nan'), 0, 0, 0, 0)
    bad_text = bytes([0xFF, 0xFC, 3]) + b'\x01\x02\x03'
    good = legacy.encode_text('OK')
    frames = parser.feed(b'\x00\x13garbage' + bad_telemetry + bad_text + good)
    assert frames == [legacy.Text('OK')]
    assert parser.stats.implausible >= 2 and parser.stats.resyncs >= 1


def test_robot_receiver_legacy_and_extension():
    rx = RobotReceiver()
    stream = (
        legacy.encode_ping()
        + legacy.encode_movement(legacy.Movement(speed=0.2))
        + legacy.encode_motor_power(False)
        + ext.encode_command(ext.Cmd.HELLO, 1, bytes([1]))
    )
    frames = rx.feed(stream)
    assert isinstance(frames[0], PingFrame) and frames[1].speed == pytest.approx(0.2)
    assert isinstance(frames[2], LegacyCommand) and frames[2].code == 0xFA
    assert frames[3].type == ext.Cmd.HELLO
    # misaligned by garbage: slides back into sync; a ping-looking byte is not trusted meanwhile
    frames = rx.feed(b'\x99\x01\x37' + ext.encode_command(ext.Cmd.STOP_TRIAL, 2))
    assert [type(f).__name__ for f in frames] == ['CommandFrame'] and rx.stats.resyncs == 1


def test_robot_receiver_recovers_from_a_partial_frame_with_pings_alone():
    # a port that vanished mid-frame leaves bytes behind; afterwards only keep-alives flow
    rx = RobotReceiver()
    rx.feed(legacy.encode_ping()[:4])
    frames = rx.feed(legacy.encode_ping() * 5 + legacy.encode_motor_power(True))
    assert sum(isinstance(f, PingFrame) for f in frames) >= 4 and isinstance(
        frames[-1], LegacyCommand
    )
    # while resynchronising, a ping-looking window with non-zero padding is not trusted
    rx2 = RobotReceiver()
    frames = rx2.feed(b'\x99' + bytes([0x37, 1, 2, 3, 4, 5, 6, 7, 8, 9]))
    assert frames == [] and rx2.stats.resyncs == 1
