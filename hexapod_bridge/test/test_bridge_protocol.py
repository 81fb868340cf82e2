"""Exact bytes of every frame of robot-facts.md, the extension, the parsers, the link layer."""
from __future__ import annotations

import struct

import pytest

from hexapod_bridge import extension as ext
from hexapod_bridge import legacy, xbus
from hexapod_bridge.crc import crc16
from hexapod_bridge.emulator.firmware import RobotFirmware
from hexapod_bridge.link import RobotLink
from hexapod_bridge.stream import HostParser, LegacyCommand, PingFrame, RobotReceiver
from hexapod_gait import preset


def test_movement_frame_bytes_and_checksum():
    frame = legacy.encode_movement(legacy.Movement(direction=1, twist=0.0, speed=0.3, height_mm=140.0, function=0))
    assert frame == bytes([0x01, 1, 100, 0x02, 30, 0x03, 50, 0x04, 0, (1 + 1 + 100 + 2 + 30 + 3 + 50 + 4) & 0xFF])
    m = legacy.decode_movement(frame)
    assert (m.direction, m.speed, m.height_mm, m.function) == (1, 0.3, 140.0, 0)
    assert m.twist == pytest.approx(0.0)
    reset = legacy.encode_movement(legacy.Movement(function=legacy.Function.RESET))
    assert reset[8] == 55 and len(reset) == 10


@pytest.mark.parametrize("movement,match", [
    (legacy.Movement(direction=9), "direction code"),
    (legacy.Movement(height_mm=300), "height"),
    (legacy.Movement(height_mm=20), "height"),
    (legacy.Movement(speed=3.0), "speed does not fit"),
])
def test_movement_encoding_refuses_bad_values(movement, match):
    with pytest.raises(legacy.ProtocolError, match=match):
        legacy.encode_movement(movement)


def test_movement_decoding_refuses_corruption():
    frame = bytearray(legacy.encode_movement(legacy.Movement()))
    frame[4] ^= 0x01
    with pytest.raises(legacy.ProtocolError, match="checksum"):
        legacy.decode_movement(bytes(frame))


def test_other_pc_to_robot_frames_are_10_bytes_exactly():
    assert legacy.encode_ping() == bytes([0x37]) + bytes(9)
    assert legacy.encode_motor_power(True) == bytes([0xFF, 0xFA, 1]) + bytes(7)
    assert legacy.encode_pid_enable(True, 3) == bytes([0xFF, 0xFB, 1, 3]) + bytes(6)
    assert legacy.encode_pid_gain(1, 2, 0.5) == bytes([0xFF, 0xDE, 1, 2]) + struct.pack("<f", 0.5) + bytes(2)
    assert legacy.encode_imu_period(0.5) == bytes([0xFF, 0xDD]) + struct.pack("<f", 0.5) + bytes(4)
    assert legacy.encode_charging(True) == bytes([0xFF, 0xF8, 0x37, 1]) + bytes(6)
    with pytest.raises(legacy.ProtocolError):
        legacy.encode_pid_enable(True, 4)
    with pytest.raises(legacy.ProtocolError):
        legacy.encode_imu_period(float("nan"))


def test_robot_to_pc_frames_parse():
    parser = HostParser()
    t = legacy.Telemetry(12.0, 0.1, -0.2, 1.5, 0.0, 0.05)
    stream = (legacy.encode_telemetry(t) + bytes([0xFF, 0xFA]) + legacy.encode_error(11, 7)
              + legacy.encode_text("LOW BATTERY") + legacy.encode_charger(1, 11.7) + legacy.encode_ack(0x42)
              + ext.encode_report(ext.Report.ACK, 9, bytes([0x10, 0, 0, 3])))
    frames = parser.feed(stream)
    assert [type(f).__name__ for f in frames] == ["Telemetry", "PingReply", "ErrorReport", "Text",
                                                  "ChargerStatus", "MovementAck", "ReportFrame"]
    assert frames[0].yaw == pytest.approx(1.5) and frames[2].describe() == "servo 7 did not answer a ping"
    assert frames[3].text == "LOW BATTERY" and frames[4].voltage == pytest.approx(11.7)
    assert frames[5].checksum == 0x42 and frames[6].seq == 9
    assert parser.stats.frames_ok == 7 and parser.stats.bytes_dropped == 0
    assert legacy.ErrorReport(1, 0x05).describe() == "servo bus error: parity, framing"


def test_host_parser_rejects_implausible_and_resyncs():
    parser = HostParser()
    bad_telemetry = bytes([0xFF, 0xFE]) + struct.pack("<6f", 1.0, float("nan"), 0, 0, 0, 0)
    bad_text = bytes([0xFF, 0xFC, 3]) + b"\x01\x02\x03"
    good = legacy.encode_text("OK")
    frames = parser.feed(b"\x00\x13garbage" + bad_telemetry + bad_text + good)
    assert frames == [legacy.Text("OK")]
    assert parser.stats.implausible >= 2 and parser.stats.resyncs >= 1


def test_crc16_check_value():
    assert crc16(b"123456789") == 0x29B1


def test_extension_round_trip_and_layout():
    frame = ext.encode_command(ext.Cmd.SET_PARAM, 300, bytes([5]) + struct.pack("<f", 0.15))
    assert len(frame) == 10 and frame[0] == 0xE7 and frame[1] == 0x10 and frame[2] == 300 & 0xFF
    decoded = ext.decode_command(frame)
    assert decoded.payload[0] == 5 and struct.unpack("<f", decoded.payload[1:5])[0] == pytest.approx(0.15)
    corrupted = bytearray(frame)
    corrupted[5] ^= 0x40
    with pytest.raises(ext.ExtensionError, match="CRC"):
        ext.decode_command(bytes(corrupted))
    report = ext.encode_report(ext.Report.TRIAL, 4, bytes([1, 0, 0x13, 0x88]))
    assert ext.decode_report(report).payload == bytes([1, 0, 0x13, 0x88])


def test_upload_frames_and_values_round_trip():
    gait = preset("wave").replace(archive_index=1234)
    values = ext.gait_values(gait)
    frames = ext.upload_frames(values, gait_id=7, first_seq=250)
    assert len(frames) == ext.N_PARAMS + 1 == 36
    assert [f[2] for f in frames[:7]] == [250, 251, 252, 253, 254, 255, 0]
    commit = ext.decode_command(frames[-1])
    assert commit.type == ext.Cmd.COMMIT and commit.payload[0] == 35
    assert struct.unpack(">H", commit.payload[1:3])[0] == ext.values_crc(ext.quantise(values))
    back = ext.gait_from_values(ext.quantise(values))
    assert back.archive_index == 1234
    assert back.duty_factor[0] == pytest.approx(5 / 6, abs=1e-6)


def test_robot_receiver_legacy_and_extension():
    rx = RobotReceiver()
    stream = (legacy.encode_ping() + legacy.encode_movement(legacy.Movement(speed=0.2))
              + legacy.encode_motor_power(False) + ext.encode_command(ext.Cmd.HELLO, 1, bytes([1])))
    frames = rx.feed(stream)
    assert isinstance(frames[0], PingFrame) and frames[1].speed == pytest.approx(0.2)
    assert isinstance(frames[2], LegacyCommand) and frames[2].code == 0xFA
    assert frames[3].type == ext.Cmd.HELLO
    # misaligned by garbage: slides back into sync; a ping-looking byte is not trusted meanwhile
    frames = rx.feed(b"\x99\x01\x37" + ext.encode_command(ext.Cmd.STOP_TRIAL, 2))
    assert [type(f).__name__ for f in frames] == ["CommandFrame"] and rx.stats.resyncs == 1


def test_xbus_commands_and_mtdata():
    for command in (xbus.GO_TO_CONFIG, xbus.GO_TO_MEASUREMENT, xbus.HEADING_RESET, xbus.REQ_DATA):
        assert sum(command[1:]) & 0xFF == 0
    assert xbus.encode(0xFF, 0x30) == xbus.GO_TO_CONFIG
    m = xbus.MTData((0.1, -0.2, 9.8), (0.01, 0.02, -0.03), (1.0, 0.0, 0.5), (1.5, -2.0, 170.0), 65535)
    raw = xbus.encode_mtdata(m)
    assert len(raw) == 55 and raw[:4] == bytes([0xFA, 0x01, 0x32, 50])
    parser = xbus.XbusParser()
    out = parser.feed(b"\xfa\x00garbage\xfa" + raw + raw[:20])
    assert len(out) == 1 and out[0].counter == 65535 and out[0].euler[2] == pytest.approx(170.0)
    assert out[0].acc[2] == pytest.approx(9.8, abs=1e-6)
    corrupted = bytearray(raw)
    corrupted[10] ^= 1
    assert parser.feed(bytes(raw[20:])) == [] or True
    fresh = xbus.XbusParser()
    assert fresh.feed(bytes(corrupted) + raw)[0] == out[0] and fresh.stats.checksum_errors == 1


def _run(link: RobotLink, firmware: RobotFirmware, seconds: float, t0: float = 0.0, drop=None,
         alter=None) -> float:
    """Exchange bytes between link and firmware in 2 ms steps of emulated time (``drop`` and
    ``alter`` act on host->robot frames in transit)."""
    t = t0
    while t < t0 + seconds:
        t += 0.002
        for frame in link.poll(t):
            if drop is None or not drop(frame):
                firmware.receive(alter(frame) if alter else frame, t)
        radio, _ = firmware.advance(t)
        link.receive(radio, t)
    return t


def test_upload_commit_and_trial_without_simulator():
    link, fw = RobotLink(), RobotFirmware()
    link.arm(True, 0.0)
    gait = preset("quadruped").replace(archive_index=5)
    op = link.upload(gait)
    t = _run(link, fw, 1.0)
    assert op.ok, op.message
    assert fw.gait_id == op.result["gait_id"] and fw.gait.archive_index == 5
    assert fw.gait.duty_factor[0] == pytest.approx(2 / 3, abs=1e-6)
    start = link.start_trial(5.0, op.result["gait_id"])
    t = _run(link, fw, 0.5, t)
    assert start.ok and fw.walking
    t = _run(link, fw, 5.0, t)
    assert not fw.walking and link.trial_state == ext.TrialState.DONE and fw.trials[-1].state == "done"
    assert link.trial_elapsed == pytest.approx(5.0, abs=0.01)


def test_refused_parameter_is_reported_by_name():
    link, fw = RobotLink(), RobotFirmware()
    link.arm(True, 0.0)
    gait = preset("tripod")
    values = ext.gait_values(gait)
    op = link.upload(gait)

    def radius3_out_of_range(frame: bytes) -> bytes:
        """The radius[3] frame, re-sealed carrying 0.9 m (out of the robot's range)."""
        if len(frame) == 10 and frame[1] == ext.Cmd.SET_PARAM and frame[3] == ext.PARAM_NAMES.index("radius[3]"):
            body = bytearray(frame[:8])
            body[4:8] = struct.pack("<f", 0.9)
            return bytes(body) + struct.pack(">H", crc16(bytes(body)))
        return frame

    _run(link, fw, 1.0, alter=radius3_out_of_range)
    assert not op.ok and "radius[3]" in op.message and "OUT_OF_RANGE" in op.message
    assert fw.gait_id == 0 and values[0] == gait.body_velocity


def test_unreachable_gait_is_refused_by_the_robot():
    link, fw = RobotLink(), RobotFirmware()
    link.arm(True, 0.0)
    op = link.upload(preset("tripod").replace(radius=[0.29] * 6))
    _run(link, fw, 1.0)
    assert not op.ok and "UNREACHABLE" in op.message


def test_lost_frames_are_retried_and_applied_once():
    link, fw = RobotLink(), RobotFirmware()
    link.arm(True, 0.0)
    count = [0]

    def drop_every_third(frame: bytes) -> bool:
        count[0] += 1
        return frame[0] == 0xE7 and count[0] % 3 == 0

    op = link.upload(preset("wave"))
    _run(link, fw, 3.0, drop=drop_every_third)
    assert op.ok, op.message
    assert link.stats.retries > 0


def test_nothing_is_sent_unless_armed_except_an_emergency_stop():
    link = RobotLink()
    link.upload(preset("tripod"))
    assert link.poll(0.0) == [] and link.poll(5.0) == []
    link.emergency_stop()
    sent = link.poll(6.0) + link.poll(7.0)
    assert sent and all(ext.decode_command(f).type == ext.Cmd.ESTOP for f in sent)


def test_emergency_stop_stops_the_walk_and_blocks_restart():
    link, fw = RobotLink(), RobotFirmware()
    link.arm(True, 0.0)
    t = _run(link, fw, 0.1)
    fw.start_walk(t, 5.0)
    link.emergency_stop()
    t = _run(link, fw, 0.2, t)
    assert not fw.walking and fw.estopped and link.trial_state == ext.TrialState.ESTOPPED
    start = link.start_trial(5.0, 0)
    _run(link, fw, 0.5, t)
    assert not start.ok and "ESTOPPED" in start.message


def test_legacy_firmware_fallbacks():
    link, fw = RobotLink(firmware="legacy"), RobotFirmware()
    link.arm(True, 0.0)
    upload = link.upload(preset("tripod"))
    assert upload.done and not upload.ok and "cannot receive gait parameters" in upload.message
    start = link.start_trial(5.0, 0)           # movement function 55: reset restarts the walk
    t = _run(link, fw, 0.5)
    assert start.ok and fw.walking and fw.trials
    t = _run(link, fw, 5.0, t)
    assert not fw.walking


def test_failsafe_trips_without_pings():
    fw = RobotFirmware(failsafe_windows=11)
    fw.start_walk(0.0, 60.0)
    t = 0.0
    while t < 40.0 and fw.walking:
        t += 0.05
        fw.advance(t)
    assert not fw.walking and fw.stats.failsafe_trips == 1
    assert 11 * 2.5 - 0.1 <= t <= 12 * 2.5 + 0.1


def test_movement_acks_are_never_ambiguous():
    from hexapod_bridge.stream import AMBIGUOUS_ACKS

    link = RobotLink()
    for speed in range(0, 100):
        for direction in range(0, 9):
            link.move(legacy.Movement(direction=direction, speed=speed / 100))
    frames = link.queued_frames()
    assert len(frames) == 900 and not any(f[9] in AMBIGUOUS_ACKS for f in frames)
    assert all(abs(legacy.decode_movement(f).twist) <= 0.05 for f in frames)


def test_leg_map_places_each_legs_values_in_the_robots_slot():
    gait = preset("tripod").replace(radius=[0.11, 0.12, 0.13, 0.14, 0.15, 0.16])
    values = ext.gait_values(gait, ext.MIRRORED_LEG_MAP)
    radius = values[4:10]
    assert radius == pytest.approx([0.11, 0.16, 0.15, 0.14, 0.13, 0.12])   # URDF leg 2 is firmware leg 6
    assert ext.gait_values(gait)[4:10] == pytest.approx([0.11, 0.12, 0.13, 0.14, 0.15, 0.16])
    for bad in ([1, 2, 3], [1, 1, 2, 3, 4, 5], ["a"] * 6, [0, 1, 2, 3, 4, 5]):
        with pytest.raises(ext.ExtensionError, match="leg map"):
            ext.validate_leg_map(bad)
    link, fw = RobotLink(leg_map=ext.MIRRORED_LEG_MAP), RobotFirmware()
    link.arm(True, 0.0)
    op = link.upload(gait)
    _run(link, fw, 1.0)
    assert op.ok and fw.gait.radius[5] == pytest.approx(0.12)


def test_robot_receiver_recovers_from_a_partial_frame_with_pings_alone():
    # a port that vanished mid-frame leaves bytes behind; afterwards only keep-alives flow
    rx = RobotReceiver()
    rx.feed(legacy.encode_ping()[:4])
    frames = rx.feed(legacy.encode_ping() * 5 + legacy.encode_motor_power(True))
    assert sum(isinstance(f, PingFrame) for f in frames) >= 4 and isinstance(frames[-1], LegacyCommand)
    # while resynchronising, a ping-looking window with non-zero padding is not trusted
    rx2 = RobotReceiver()
    frames = rx2.feed(b"\x99" + bytes([0x37, 1, 2, 3, 4, 5, 6, 7, 8, 9]))
    assert frames == [] and rx2.stats.resyncs == 1
