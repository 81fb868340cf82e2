# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Reliability of the radio and IMU framing.

Under a noisy channel, garbage bursts, a saturated link, and fuzzing. Seeded; each test prints its
figures (pytest -s shows them).
"""

from __future__ import annotations

import math
import struct

from hexapod_bridge.emulator.firmware import RobotFirmware
from hexapod_bridge.link import RobotLink
from hexapod_bridge.protocol import extension as ext
from hexapod_bridge.protocol import legacy, xbus
from hexapod_bridge.protocol.stream import CHUNK, HostParser, MAX_TEXT, RobotReceiver
from hexapod_gait import preset
from hypothesis import given, HealthCheck, settings
from hypothesis import strategies as st
import numpy as np
import pytest

N_FRAMES = 100_000


def noisy_channel(
    data: bytes, rng: np.random.Generator, p_sub: float = 0.01, p_indel: float = 0.001
) -> bytes:
    """1 % byte substitution, 0.1 % insertion/deletion (half each), per byte."""
    arr = np.frombuffer(data, dtype=np.uint8).copy()
    sub = rng.random(arr.size) < p_sub
    # always a change
    arr[sub] = (arr[sub].astype(np.int32) + rng.integers(1, 256, sub.sum())).astype(np.uint8)
    u = rng.random(arr.size)
    deleted = u < p_indel / 2
    inserted = (u >= p_indel / 2) & (u < p_indel)
    out = bytearray()
    extra = rng.integers(0, 256, inserted.sum()).astype(np.uint8)
    k = 0
    pieces, last = [], 0
    for i in np.flatnonzero(deleted | inserted):
        pieces.append(arr[last:i].tobytes())
        if inserted[i]:
            pieces.append(bytes([extra[k]]))
            k += 1
            pieces.append(arr[[i]].tobytes())
        last = i + 1
    pieces.append(arr[last:].tobytes())
    out.extend(b''.join(pieces))
    return bytes(out)


def feed_in_chunks(parser, data: bytes, rng: np.random.Generator) -> list:
    frames, i = [], 0
    while i < len(data):
        n = int(rng.integers(1, 300))
        frames.extend(parser.feed(data[slice(i, i + n)]))
        i += n
    return frames


def _report(i: int) -> bytes:
    # TRIAL report whose 24-bit "elapsed" field carries the frame number: content is unique
    return ext.encode_report(
        ext.Report.TRIAL, i & 0xFF, bytes([1]) + (i & 0xFFFFFF).to_bytes(3, 'big')
    )


def test_crc_frames_robot_to_pc_never_accept_corruption_and_every_loss_is_counted():
    rng = np.random.default_rng(1)
    sent = [_report(i) for i in range(N_FRAMES)]
    received = noisy_channel(b''.join(sent), rng)
    parser = HostParser()
    frames = [f for f in feed_in_chunks(parser, received, rng) if isinstance(f, ext.ReportFrame)]
    corrupted = 0
    indices = []
    for f in frames:
        index = int.from_bytes(f.payload[1:4], 'big')
        if index >= N_FRAMES or _report(index)[2:8] != bytes([f.type, f.seq]) + f.payload:
            corrupted += 1
        else:
            indices.append(index)
    gaps = sum(ext.sequence_gap(a & 0xFF, b & 0xFF) for a, b in zip([-1] + indices[:-1], indices))
    damaged = N_FRAMES - len(indices)
    print(
        f'\nrobot->PC CRC frames: sent {N_FRAMES}, accepted intact {len(indices)}, damaged'
        f' {damaged} ({100 * damaged / N_FRAMES:.2f} %), corrupted accepted {corrupted}, CRC'
        f' errors {parser.stats.checksum_errors}, resyncs {parser.stats.resyncs}, bytes dropped'
        f' {parser.stats.bytes_dropped}, losses seen by sequence gaps {gaps}'
    )
    assert corrupted == 0
    assert damaged > 5000  # the channel really did damage ~10 % of frames
    assert gaps == damaged  # every damaged frame shows up as a sequence gap
    assert indices == sorted(indices)


def test_crc_frames_pc_to_robot_never_accept_corruption_and_every_loss_is_counted():
    rng = np.random.default_rng(2)
    sent = [
        ext.encode_command(
            ext.Cmd.SET_PARAM, i, bytes([i % ext.N_PARAMS]) + struct.pack('<f', float(i))
        )
        for i in range(N_FRAMES)
    ]
    received = noisy_channel(b''.join(sent), rng)
    rx = RobotReceiver()
    frames = [f for f in feed_in_chunks(rx, received, rng) if isinstance(f, ext.CommandFrame)]
    corrupted, indices = 0, []
    for f in frames:
        value = struct.unpack('<f', f.payload[1:5])[0]
        i = (
            int(value)
            if math.isfinite(value) and value == int(value) and 0 <= value < N_FRAMES
            else -1
        )
        if i < 0 or sent[i] != ext.encode_command(ext.Cmd(f.type), f.seq, f.payload):
            corrupted += 1
        else:
            indices.append(i)
    gaps = sum(ext.sequence_gap(a & 0xFF, b & 0xFF) for a, b in zip([-1] + indices[:-1], indices))
    damaged = N_FRAMES - len(indices)
    print(
        f'\nPC->robot CRC frames: sent {N_FRAMES}, accepted intact {len(indices)}, damaged'
        f' {damaged}, corrupted accepted {corrupted}, CRC errors {rx.stats.checksum_errors},'
        f' resyncs {rx.stats.resyncs}, losses seen by sequence gaps {gaps}'
    )
    assert corrupted == 0 and damaged > 5000 and gaps == damaged


def test_legacy_frames_false_accept_rate_is_measured_and_implausible_values_rejected():
    rng = np.random.default_rng(3)
    # robot -> PC: telemetry (no checksum) and charger status (8-bit sum), alternating
    sent, kinds = [], []
    for i in range(N_FRAMES // 2):
        t = legacy.Telemetry(float(i), *(rng.uniform(-0.5, 0.5, 3)), 0.0, 0.0)
        sent.append(legacy.encode_telemetry(t))
        kinds.append(t)
        c = legacy.ChargerStatus(i % 3, float(np.float32(rng.uniform(10, 13))))
        sent.append(legacy.encode_charger(c.status, c.voltage))
        kinds.append(c)
    received = noisy_channel(b''.join(sent), rng)
    parser = HostParser()
    frames = feed_in_chunks(parser, received, rng)
    truth_t = {k.counter: k for k in kinds if isinstance(k, legacy.Telemetry)}
    truth_c = {(k.status, k.voltage) for k in kinds if isinstance(k, legacy.ChargerStatus)}
    tele = [f for f in frames if isinstance(f, legacy.Telemetry)]
    charger = [f for f in frames if isinstance(f, legacy.ChargerStatus)]
    false_t = sum(1 for f in tele if not _exact(f, truth_t.get(f.counter)))
    false_c = sum(1 for f in charger if (f.status, f.voltage) not in truth_c)
    damaged_t = (N_FRAMES // 2) - (len(tele) - false_t)
    damaged_c = (N_FRAMES // 2) - (len(charger) - false_c)
    rate_t = false_t / max(1, damaged_t + false_t)
    rate_c = false_c / max(1, damaged_c + false_c)
    print(
        f'\nlegacy telemetry (no checksum): {len(tele)} accepted, {false_t} of them corrupted:'
        f' false-accept rate {100 * rate_t:.2f} % of damaged frames; implausible rejected'
        f' {parser.stats.implausible}'
    )
    print(
        f'legacy charger (8-bit sum): {len(charger)} accepted, {false_c} corrupted: false-accept'
        f' rate {100 * rate_c:.3f} % of damaged frames; checksum errors'
        f' {parser.stats.checksum_errors}'
    )
    for f in tele:  # whatever slipped through is at least physically possible
        assert all(
            math.isfinite(v)
            for v in (f.counter, f.pitch, f.roll, f.yaw, f.slope_pitch, f.slope_roll)
        )
        assert (
            abs(f.pitch) <= math.pi
            and abs(f.roll) <= math.pi
            and abs(f.slope_pitch) <= math.pi / 2
        )
    for f in charger:
        assert 0 <= f.voltage <= 60
    # an 8-bit sum lets through roughly 1/256 of corruptions plus resync artefacts
    assert rate_c < 0.02
    # PC -> robot movement frames (8-bit sum): false accepts counted by the robot side
    moves = [
        legacy.encode_movement(
            legacy.Movement(direction=int(d), speed=s / 100, height_mm=280 * h / 100)
        )
        for d, s, h in zip(
            rng.integers(0, 9, 20000), rng.integers(0, 50, 20000), rng.integers(18, 86, 20000)
        )
    ]
    rx = RobotReceiver()
    got = [
        f
        for f in feed_in_chunks(rx, noisy_channel(b''.join(moves), rng), rng)
        if isinstance(f, legacy.Movement)
    ]
    valid = {legacy.decode_movement(m) for m in moves}
    false_m = sum(1 for f in got if f not in valid)
    print(
        f'legacy movement (8-bit sum), PC->robot: {len(got)} accepted, {false_m} corrupted'
        f' accepted ({100 * false_m / 20000:.3f} % of frames sent)'
    )


def _exact(a, b) -> bool:
    return b is not None and struct.pack(
        '<6f', a.counter, a.pitch, a.roll, a.yaw, a.slope_pitch, a.slope_roll
    ) == struct.pack('<6f', b.counter, b.pitch, b.roll, b.yaw, b.slope_pitch, b.slope_roll)


FAKE_HEADERS = [
    b'\xff\xfe',
    b'\xff\xe7',
    b'\xff\xfc',
    b'\xff\xfd',
    b'\xff\xf9',
    b'\xe7\x10',
    b'\xfa\x01\x32\x32',
    b'\x01',
    b'\x37',
    b'\xfa\xff',
]


def _burst(rng: np.random.Generator) -> bytes:
    n = int(rng.integers(1, 513))
    data = bytearray(rng.integers(0, 256, n).astype(np.uint8).tobytes())
    for _ in range(int(rng.integers(0, 8))):
        h = FAKE_HEADERS[int(rng.integers(len(FAKE_HEADERS)))]
        at = int(rng.integers(0, n))
        data[slice(at, at + len(h))] = h
    return bytes(data[:n])


def _host_case():
    def index_of(f):
        return int.from_bytes(f.payload[1:4], 'big') if isinstance(f, ext.ReportFrame) else None

    return _report, HostParser(), index_of, CHUNK + 3 + MAX_TEXT


def _robot_case():
    def make(i):
        return ext.encode_command(ext.Cmd.SET_PARAM, i, bytes([0]) + struct.pack('<f', float(i)))

    def index_of(f):
        if isinstance(f, ext.CommandFrame):
            return int(struct.unpack('<f', f.payload[1:5])[0])
        return None

    return make, RobotReceiver(), index_of, CHUNK + legacy.FRAME_LEN


def _xbus_case():
    def make(i):
        return xbus.encode_mtdata(
            xbus.MTData((0.0, 0.0, 9.8), (0.0, 0.0, 0.0), (0, 0, 0), (0, 0, 0), i & 0xFFFF)
        )

    def index_of(f):
        return f.counter if isinstance(f, xbus.MTData) else None

    return make, xbus.XbusParser(), index_of, 256 + 5 + xbus.MAX_DATA


#: Per stream kind: (frame maker, parser, frame -> index or None, buffer bound in bytes).
_BURST_CASES = {'host': _host_case, 'robot': _robot_case, 'xbus': _xbus_case}


@pytest.mark.parametrize('kind', ['host', 'robot', 'xbus'])
def test_garbage_bursts_resync_within_one_frame_and_buffer_stays_bounded(kind):
    rng = np.random.default_rng({'host': 4, 'robot': 5, 'xbus': 6}[kind])
    n_bursts, per_gap = 500, 4
    make, parser, index_of, bound = _BURST_CASES[kind]()
    stream, first_after = bytearray(), []
    i = 0
    for _ in range(n_bursts):
        for _ in range(per_gap):
            stream += make(i)
            i += 1
        stream += _burst(rng)
        first_after.append(i)
    stream += make(i) + make(i + 1)
    got = {index_of(f) for f in feed_in_chunks(parser, bytes(stream), rng)} - {None}
    lost_first = sum(1 for k in first_after if k not in got)
    lost_second = sum(1 for k in first_after if k + 1 not in got)
    print(
        f'\n{kind}: {n_bursts} bursts of 1-512 bytes with fake headers: first frame after a burst'
        f' lost {lost_first} times, second frame lost {lost_second} times; max buffer'
        f' {parser.stats.max_buffer} B (bound {bound} B)'
    )
    assert lost_second == 0  # back in sync within one frame
    assert parser.stats.max_buffer <= bound


def test_keepalive_never_misses_the_failsafe_window_on_a_saturated_link():
    link, fw = RobotLink(ping_period=1.0), RobotFirmware(failsafe_windows=11)
    link.arm(True, 0.0)
    for k in range(400):  # more than the link can carry in 60 s
        link.upload(preset('tripod').replace(archive_index=k))
    ping_times, t, wire_free = [], 0.0, 0.0
    while t < 60.0:
        t += 0.001
        for frame in link.poll(t):
            wire_free = max(wire_free, t) + len(frame) / 1920.0  # 19200 baud on the wire
            if frame[0] == legacy.PING_BYTE:
                ping_times.append(wire_free)
            fw.receive(frame, wire_free)
        radio, _ = fw.advance(t)
        link.receive(radio, t)
    gaps = np.diff(ping_times)
    utilisation = link.stats.frames_sent * 10 / (1920.0 * 60.0)
    print(
        f'\nsaturated link: utilisation {100 * utilisation:.0f} %, {len(ping_times)} pings, max'
        f' gap between pings {gaps.max():.3f} s (failsafe check window 2.5 s), missed windows'
        f' {fw.stats.missed_windows}, failsafe trips {fw.stats.failsafe_trips}, uploads'
        f' acknowledged {link.stats.acks}'
    )
    assert utilisation > 0.8
    assert gaps.max() < 2.5 and fw.stats.missed_windows == 0 and fw.stats.failsafe_trips == 0


FUZZ = settings(
    max_examples=400, derandomize=True, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)


@FUZZ
@given(st.lists(st.binary(max_size=600), max_size=8))
def test_fuzz_host_parser_never_raises(chunks):
    parser = HostParser()
    for chunk in chunks:
        parser.feed(chunk)
    assert len(parser.buffer) <= CHUNK + 3 + MAX_TEXT


@pytest.mark.slow
@FUZZ
@given(st.lists(st.binary(max_size=600), max_size=8))
def test_fuzz_robot_receiver_and_firmware_never_raise(chunks):
    rx, fw = RobotReceiver(), RobotFirmware()
    for k, chunk in enumerate(chunks):
        rx.feed(chunk)
        fw.receive(chunk, 0.01 * k)
        fw.advance(0.01 * k)
    assert len(rx.buffer) < legacy.FRAME_LEN


@FUZZ
@given(st.lists(st.binary(max_size=600), max_size=8))
def test_fuzz_xbus_parser_never_raises(chunks):
    parser = xbus.XbusParser()
    for chunk in chunks:
        parser.feed(chunk)
    assert len(parser.buffer) <= 256 + 5 + xbus.MAX_DATA


@FUZZ
@given(st.binary(min_size=10, max_size=10))
def test_fuzz_frame_decoders_raise_only_their_own_errors(raw):
    for decode, error in (
        (legacy.decode_movement, legacy.ProtocolError),
        (ext.decode_command, ext.ExtensionError),
        (ext.decode_report, ext.ExtensionError),
    ):
        try:
            decode(raw)
        except error:
            pass


@FUZZ
@given(st.lists(st.binary(min_size=1, max_size=64), max_size=20))
def test_fuzz_link_receive_never_raises(chunks):
    link = RobotLink()
    link.arm(True, 0.0)
    link.upload(preset('tripod'))
    for k, chunk in enumerate(chunks):
        link.receive(chunk, 0.01 * k)
        link.poll(0.01 * k)
