# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The host link layer (hexapod_bridge.link) against the emulated firmware.

Uploads, trials, retries, arming, e-stop.
"""

from __future__ import annotations

import struct

from hexapod_bridge.emulator.firmware import RobotFirmware
from hexapod_bridge.link import RobotLink
from hexapod_bridge.protocol import extension as ext
from hexapod_bridge.protocol import legacy
from hexapod_bridge.protocol.crc import crc16
from hexapod_gait import preset
import pytest


def _run(
    link: RobotLink,
    firmware: RobotFirmware,
    seconds: float,
    t0: float = 0.0,
    drop=None,
    alter=None,
) -> float:
    """
    Exchange bytes between link and firmware in 2 ms steps of emulated time.

    ``drop`` and ``alter`` act on host->robot frames in transit.
    """
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
    gait = preset('quadruped').replace(archive_index=5)
    op = link.upload(gait)
    t = _run(link, fw, 1.0)
    assert op.ok, op.message
    assert fw.gait_id == op.result['gait_id'] and fw.gait.archive_index == 5
    assert fw.gait.duty_factor[0] == pytest.approx(2 / 3, abs=1e-6)
    start = link.start_trial(5.0, op.result['gait_id'])
    t = _run(link, fw, 0.5, t)
    assert start.ok and fw.walking
    t = _run(link, fw, 5.0, t)
    assert (
        not fw.walking
        and link.trial_state == ext.TrialState.DONE
        and fw.trials[-1].state == 'done'
    )
    assert link.trial_elapsed == pytest.approx(5.0, abs=0.01)


def test_refused_parameter_is_reported_by_name():
    link, fw = RobotLink(), RobotFirmware()
    link.arm(True, 0.0)
    gait = preset('tripod')
    values = ext.gait_values(gait)
    op = link.upload(gait)

    def radius3_out_of_range(frame: bytes) -> bytes:
        """Return the radius[3] frame, re-sealed carrying 0.9 m (out of the robot's range)."""
        if (
            len(frame) == 10
            and frame[1] == ext.Cmd.SET_PARAM
            and frame[3] == ext.PARAM_NAMES.index('radius[3]')
        ):
            body = bytearray(frame[:8])
            body[4:8] = struct.pack('<f', 0.9)
            return bytes(body) + struct.pack('>H', crc16(bytes(body)))
        return frame

    _run(link, fw, 1.0, alter=radius3_out_of_range)
    assert not op.ok and 'radius[3]' in op.message and 'OUT_OF_RANGE' in op.message
    assert fw.gait_id == 0 and values[0] == gait.body_velocity


def test_unreachable_gait_is_refused_by_the_robot():
    link, fw = RobotLink(), RobotFirmware()
    link.arm(True, 0.0)
    op = link.upload(preset('tripod').replace(radius=[0.29] * 6))
    _run(link, fw, 1.0)
    assert not op.ok and 'UNREACHABLE' in op.message and not op.unanswered  # an answer


def test_lost_frames_are_retried_and_applied_once():
    link, fw = RobotLink(), RobotFirmware()
    link.arm(True, 0.0)
    count = [0]

    def drop_every_third(frame: bytes) -> bool:
        count[0] += 1
        return frame[0] == 0xE7 and count[0] % 3 == 0

    op = link.upload(preset('wave'))
    _run(link, fw, 3.0, drop=drop_every_third)
    assert op.ok, op.message
    assert link.stats.retries > 0


def test_nothing_is_sent_unless_armed_except_an_emergency_stop():
    link = RobotLink()
    link.upload(preset('tripod'))
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
    assert not start.ok and 'ESTOPPED' in start.message


def test_legacy_firmware_fallbacks():
    link, fw = RobotLink(firmware='legacy'), RobotFirmware()
    link.arm(True, 0.0)
    upload = link.upload(preset('tripod'))
    assert upload.done and not upload.ok and 'cannot receive gait parameters' in upload.message
    start = link.start_trial(5.0, 0)  # movement function 55: reset restarts the walk
    t = _run(link, fw, 0.5)
    assert start.ok and fw.walking and fw.trials
    t = _run(link, fw, 5.0, t)
    assert not fw.walking


def test_movement_acks_are_never_ambiguous():
    from hexapod_bridge.protocol.stream import AMBIGUOUS_ACKS

    link = RobotLink()
    for speed in range(0, 100):
        for direction in range(0, 9):
            link.move(legacy.Movement(direction=direction, speed=speed / 100))
    frames = link.queued_frames()
    assert len(frames) == 900 and not any(f[9] in AMBIGUOUS_ACKS for f in frames)
    assert all(abs(legacy.decode_movement(f).twist) <= 0.05 for f in frames)


def test_leg_map_places_each_legs_values_in_the_robots_slot():
    gait = preset('tripod').replace(radius=[0.11, 0.12, 0.13, 0.14, 0.15, 0.16])
    values = ext.gait_values(gait, ext.MIRRORED_LEG_MAP)
    radius = values[4:10]
    # URDF leg 2 is firmware leg 6
    assert radius == pytest.approx([0.11, 0.16, 0.15, 0.14, 0.13, 0.12])
    assert ext.gait_values(gait)[4:10] == pytest.approx([0.11, 0.12, 0.13, 0.14, 0.15, 0.16])
    for bad in ([1, 2, 3], [1, 1, 2, 3, 4, 5], ['a'] * 6, [0, 1, 2, 3, 4, 5]):
        with pytest.raises(ext.ExtensionError, match='leg map'):
            ext.validate_leg_map(bad)
    link, fw = RobotLink(leg_map=ext.MIRRORED_LEG_MAP), RobotFirmware()
    link.arm(True, 0.0)
    op = link.upload(gait)
    _run(link, fw, 1.0)
    assert op.ok and fw.gait.radius[5] == pytest.approx(0.12)


def test_hello_gets_the_version_and_the_servo_reports_become_events():
    link, fw = RobotLink(), RobotFirmware(servo_ping=lambda servo: servo != 9)
    assert not link.hello().ok  # unarmed: nothing may be sent
    link.arm(True, 0.0)
    t = _run(link, fw, 0.2)  # the start-up health check
    assert ('servo_failure', 9) in link.events
    link.events.clear()
    op = link.hello()
    _run(link, fw, 0.2, t)
    assert op.ok and op.result == {'major': 1, 'minor': 1}, op.message
    assert ('servo_failure', 9) in link.events and ('version', (1, 1)) in link.events
    assert not RobotLink(firmware='legacy').hello().ok


def test_a_commit_waits_for_the_robot_to_compile_before_it_is_sent_again():
    link = RobotLink()
    link.arm(True, 0.0)
    op = link.upload(preset('tripod').replace(period=10.0, body_velocity=0.02))
    commits = []
    t = 0.0
    while not commits:  # every frame once, each acknowledged but the COMMIT
        t += 0.002
        for frame in link.poll(t):
            if frame[1] == ext.Cmd.COMMIT:
                commits.append(frame)
            if frame[0] == ext.MARKER and frame[1] == ext.Cmd.SET_PARAM:
                ack = ext.encode_report(
                    ext.Report.ACK, frame[2], bytes([frame[1], 0, 0, frame[3]])
                )
                link.receive(ack, t)
    sent_at = t
    # 1200 + 120 rows at 2 ms: 2.64 s on top of the 0.25 s acknowledgement timeout
    while t < sent_at + 2.8:
        t += 0.01
        assert not any(f[1] == ext.Cmd.COMMIT for f in link.poll(t)), f'resent at {t - sent_at}'
    t += 0.2
    assert any(f[1] == ext.Cmd.COMMIT for f in link.poll(t))  # now it is sent again
    assert not op.done


@pytest.mark.parametrize('answered_for', [0.0, 0.01, 0.05])
def test_an_upload_the_robot_stops_answering_fails_with_the_reason(answered_for):
    """
    The robot falls silent mid-upload; the radio thread polls in bursts, then stalls.

    On a loaded machine the window's SET_PARAMs expire in one poll, and the first to fail its
    upload drops the others, which that poll expired too (a KeyError aborted the poll).
    """
    link, fw = RobotLink(), RobotFirmware()
    link.arm(True, 0.0)
    op, t = link.upload(preset('tripod')), 0.0
    while not op.done and t < 60.0:
        for _ in range(40):  # polls 1 ms apart...
            t += 0.001
            frames = link.poll(t)
            if t < answered_for:
                for frame in frames:
                    fw.receive(frame, t)
                link.receive(fw.advance(t)[0], t)
        t += 1.0  # ...then a stall longer than the acknowledgement timeout
    assert op.done and not op.ok and op.unanswered  # the link's fault, not a refusal
    assert op.message == f'no acknowledgement after {link.max_retries + 1} attempts'
