# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The differential tests' input: timed scripts of what a robot's UART and main loop see.

Seeded fuzz scripts (random frames of every kind, at the link's timing) and the recorded
sessions of a bridge over a faulty link; :mod:`hexapod_bridge.emulator.differential` runs
them through the model and the C++ module.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import math
import struct

from hexapod_bridge.emulator.firmware import FirmwareTiming, param_range, RobotFirmware
from hexapod_bridge.protocol import extension as ext
from hexapod_bridge.protocol import legacy
from hexapod_gait import from_genotype, GENOTYPE_SIZE
from hexapod_gait.parameters import from_omni_genotype, OMNI_GENOTYPE_SIZE
from hexapod_gait.trajectory import reachable_key_points
import numpy as np


@dataclass
class Script:
    """Timed input for a firmware: what a robot's main loop and UART would see."""

    timing: FirmwareTiming = field(default_factory=FirmwareTiming)
    start_ms: int = 0
    dead_servos: frozenset[int] = frozenset()
    leg_map: tuple[int, ...] = ext.IDENTITY_LEG_MAP  # the robot's leg number of each URDF leg
    # ('B', ms, bytes) | ('P', ms) | ('T',) | ('S',)
    events: list[tuple] = field(default_factory=list)

    def receive(self, now_ms: int, data: bytes) -> None:
        """Radio bytes arrive at ``now_ms``."""
        if len(data) > 0xFFFF:
            raise ValueError('at most 65535 bytes per event')
        self.events.append(('B', int(now_ms), bytes(data)))

    def poll(self, now_ms: int) -> None:
        """Poll the firmware from the main loop at ``now_ms``."""
        self.events.append(('P', int(now_ms)))

    def table(self) -> None:
        """Print the gait table in use."""
        self.events.append(('T',))

    def servos(self) -> None:
        """Print the servo targets last written, and how many writes there were."""
        self.events.append(('S',))

    def encode(self) -> bytes:
        """Return the script in fw_replay's binary format (tools/replay.cpp)."""
        t = self.timing
        mask = sum(1 << s for s in self.dead_servos)
        out = [
            b'H'
            + struct.pack(
                '<IHHHII6B',
                round(t.walk_duration * 1000),
                t.failsafe_windows,
                t.telemetry_ticks,
                t.ping_check_ticks,
                self.start_ms & 0xFFFFFFFF,
                mask,
                *self.leg_map,
            )
        ]
        for event in self.events:
            if event[0] == 'B':
                ms = event[1] & 0xFFFFFFFF  # the firmware's clock wraps; the model's does not
                out.append(b'B' + struct.pack('<IH', ms, len(event[2])) + event[2])
            elif event[0] == 'P':
                out.append(b'P' + struct.pack('<I', event[1] & 0xFFFFFFFF))
            else:
                out.append(event[0].encode())
        return b''.join(out)


def gait_values(gait) -> list[float]:
    """Return a gait's values in the order the firmware prints them."""
    return (
        [gait.body_velocity, gait.body_height, gait.period, gait.crab_angle]
        + [float(v) for f in ('radius', 'angle_offset', 'step_height') for v in getattr(gait, f)]
        + [float(v) for f in ('duty_factor', 'phase_offset') for v in getattr(gait, f)]
        + [float(gait.archive_index), gait.turn_rate]
    )


# ---- seeded fuzz ----------------------------------------------------------------------------
class _Fuzzer:
    """Random frames of every kind, with the timing of a 19200-baud link and a main loop."""

    def __init__(self, seed: int) -> None:
        self.rng = np.random.default_rng(seed)
        self.seq = 0
        self.sent: list[bytes] = []  # extension frames, for duplicates
        self.gait_id = 0
        self.frames = 0

    def _next_seq(self) -> int:
        self.seq = (self.seq + 1) & 0xFF
        return self.seq

    def _command(self, kind: int, payload: bytes) -> bytes:
        frame = ext._seal(bytes([ext.MARKER, kind, self._next_seq()]) + payload.ljust(5, b'\0'))
        self.sent.append(frame)
        if len(self.sent) > 200:
            del self.sent[:100]
        return frame

    def _value(self, index: int) -> float:
        lo, hi = param_range(index)
        r = self.rng.random()
        if index == 34:
            lo, hi = -1.0, 1000.0
        if r < 0.75:
            return float(self.rng.uniform(lo, hi))
        if r < 0.8:
            return float(self.rng.choice([lo, hi]))
        if r < 0.95:
            return float(self.rng.choice([lo - 1e-3, hi + 1e-3, hi * 1.5 + 1.0, -1e9]))
        return float(self.rng.choice([math.nan, math.inf, -math.inf]))

    def _random_gait_values(self) -> list[float]:
        """Return a random gait: mostly one with reachable key points, so many commits succeed."""
        rng = self.rng
        size = GENOTYPE_SIZE if rng.random() < 0.5 else OMNI_GENOTYPE_SIZE
        genes = rng.random((64, size))
        if rng.random() < 0.8:
            ok = reachable_key_points(genes)
            genes = genes[ok] if ok.any() else genes
        decode = from_genotype if size == GENOTYPE_SIZE else from_omni_genotype
        gait = decode(genes[0], int(rng.integers(-1, 9999)))
        if rng.random() < 0.15:  # any period, not only the maps' 1 s
            period = float(rng.choice([0.1, 0.25, 0.5, 0.7, 1.5, 2.0, 0.333, 10.0]))
            gait = gait.replace(period=period)
        return ext.gait_values(gait)

    def frames_of_one_step(self) -> list[bytes]:
        """Return the frames of one random step (an upload is 37 frames, most are one)."""
        rng = self.rng
        r = rng.random()
        if r < 0.22:
            index = (
                int(rng.integers(0, ext.N_PARAMS))
                if rng.random() < 0.93
                else int(rng.integers(ext.N_PARAMS, 256))
            )
            value = self._value(index) if index < ext.N_PARAMS else float(rng.normal())
            return [self._command(ext.Cmd.SET_PARAM, bytes([index]) + struct.pack('<f', value))]
        if r < 0.30:  # a whole upload, maybe a trial of it
            values = self._random_gait_values()
            self.gait_id = int(rng.integers(0, 0x10000))
            frames = []
            for i, v in enumerate(values):
                frames.append(self._command(ext.Cmd.SET_PARAM, bytes([i]) + struct.pack('<f', v)))
            crc = ext.values_crc(ext.quantise(values))
            if rng.random() < 0.05:
                crc ^= 1 << int(rng.integers(0, 16))
            frames.append(
                self._command(
                    ext.Cmd.COMMIT, bytes([ext.N_PARAMS]) + struct.pack('>HH', crc, self.gait_id)
                )
            )
            if rng.random() < 0.5:
                frames.append(self._start())
            return frames
        if r < 0.34:
            count = ext.N_PARAMS if rng.random() < 0.7 else int(rng.integers(0, 256))
            payload = bytes([count]) + struct.pack(
                '>HH', int(rng.integers(0, 0x10000)), int(rng.integers(0, 0x10000))
            )
            return [self._command(ext.Cmd.COMMIT, payload)]
        if r < 0.42:
            return [self._start()]
        if r < 0.45:
            return [self._command(ext.Cmd.STOP_TRIAL, b'')]
        if r < 0.46:
            return [self._command(ext.Cmd.ESTOP, b'')]
        if r < 0.48:
            return [self._command(ext.Cmd.HELLO, bytes([1]))]
        if r < 0.50:
            kind = int(rng.choice([0x00, 0x01, 0x16, 0x7F, 0xFF]))
            return [self._command(kind, bytes(rng.integers(0, 256, 5, dtype=np.uint8)))]
        if r < 0.64:
            return [legacy.encode_ping()]
        if r < 0.70:
            return [self._movement()]
        if r < 0.75:
            return [self._ff_command()]
        if r < 0.80 and self.sent:  # a retransmission of an earlier command
            return [self.sent[int(rng.integers(max(0, len(self.sent) - 80), len(self.sent)))]]
        if r < 0.85:
            return [bytes(rng.integers(0, 256, int(rng.integers(1, 31)), dtype=np.uint8))]
        if r < 0.87:  # garbage that looks like headers
            return [bytes(rng.choice([0xE7, 0x01, 0x37, 0xFF, 0x00], int(rng.integers(1, 25))))]
        return [legacy.encode_ping()]

    def _start(self) -> bytes:
        rng = self.rng
        gait_id = self.gait_id if rng.random() < 0.7 else int(rng.integers(0, 0x10000))
        ms = int(rng.choice([0, 1, 50, 200, 1000, 2000, 5000, 60000]))
        return self._command(
            ext.Cmd.START_TRIAL, struct.pack('>HHB', ms, gait_id, int(rng.integers(0, 2)))
        )

    def _movement(self) -> bytes:
        rng = self.rng
        body = bytes(
            [
                0x01,
                int(rng.integers(0, 10)),
                int(rng.integers(0, 256)),
                0x02,
                int(rng.integers(0, 70)),
                0x03,
                int(rng.integers(10, 95)),
                0x04,
                int(rng.choice([0, 0, 0, 0, 2, 3, 4, 5, 55, 9])),
            ]
        )
        frame = body + bytes([legacy.checksum8(body)])
        if rng.random() < 0.05:
            frame = frame[:9] + bytes([(frame[9] + 1) & 0xFF])
        return frame

    def _ff_command(self) -> bytes:
        rng = self.rng
        r = rng.random()
        if r < 0.5:
            return legacy.encode_motor_power(bool(rng.random() < 0.7))
        if r < 0.7:
            period = float(rng.choice([0.01, 0.05, 0.07, 0.5, 1.0, 60.0, 61.0, math.nan]))
            return bytes([0xFF, 0xDD]) + struct.pack('<f', period) + bytes(4)
        code = int(rng.choice([0xFB, 0xDE, 0xF8, 0xAA]))
        return bytes([0xFF, code]) + bytes(rng.integers(0, 256, 8, dtype=np.uint8))

    def corrupt(self, frame: bytes) -> bytes:
        """Damage a frame as the radio may: a changed, lost or extra byte (rarely)."""
        rng = self.rng
        r = rng.random()
        if r < 0.01:
            i = int(rng.integers(0, len(frame)))
            damaged = bytearray(frame)
            damaged[i] ^= 1 << int(rng.integers(0, 8))
            return bytes(damaged)
        if r < 0.013:
            i = int(rng.integers(0, len(frame)))
            damaged = bytearray(frame)
            del damaged[i]
            return bytes(damaged)
        if r < 0.016:
            i = int(rng.integers(0, len(frame) + 1))
            return frame[:i] + bytes([int(rng.integers(0, 256))]) + frame[i:]
        return frame


def fuzz_script(
    seed: int, frames: int, dead_servos: frozenset[int] = frozenset(), tables: float = 0.2
) -> Script:
    """
    Return a seeded script of at least ``frames`` random frames.

    ``tables`` is the chance that an upload is followed by a table print.
    """
    fuzz = _Fuzzer(seed)
    rng = fuzz.rng
    # some scripts start shortly before the firmware's millisecond clock wraps (49.7 days)
    start = (
        int(rng.integers(0, 2**31)) if rng.random() < 0.5 else 2**32 - int(rng.integers(1, 10**6))
    )
    # half the scripts are for a robot whose legs are numbered otherwise than the URDF's (drawn
    # from a stream of their own: the frames are those of the seed either way)
    maps = np.random.default_rng([seed, 1])
    leg_map = (
        tuple(int(v) for v in maps.permutation(6) + 1)
        if maps.random() < 0.5
        else ext.IDENTITY_LEG_MAP
    )
    script = Script(dead_servos=dead_servos, start_ms=start, leg_map=leg_map)
    now = script.start_ms
    sent = 0
    while sent < frames:
        step = fuzz.frames_of_one_step()
        sent += len(step)
        for frame in step:
            data = fuzz.corrupt(frame)
            if len(data) > 4 and rng.random() < 0.1:  # split across two UART reads
                cut = int(rng.integers(1, len(data)))
                script.receive(now, data[:cut])
                now += int(rng.integers(0, 10))
                script.receive(now, data[cut:])
            else:
                script.receive(now, data)
            now += int(rng.integers(0, 12))
            script.poll(now)
            if rng.random() < 0.02:
                script.servos()
        if len(step) > 30 and rng.random() < tables:
            script.table()
        if rng.random() < 0.003:  # the host goes quiet: the failsafe may trip
            end = now + int(rng.integers(1000, 40000))
            while now < end:
                now += int(rng.integers(20, 120))
                script.poll(now)
        else:
            now += int(rng.integers(0, 40))
            script.poll(now)
    return script


#: The link faults of the bridge's link tests, each replayable through both firmwares.
LINK_FAULTS = ('clean', 'garbage', 'truncation', 'duplicates', 'lost_acks', 'port_vanishes')


def link_session_script(fault: str, seed: int = 0) -> Script:
    """
    Record what the robot receives in a bridge session over a faulty link; return it as a Script.

    The host is hexapod_bridge's RobotLink, armed, uploading the four presets and two random
    reachable gaits, walking a 1 s trial of each, stopping one early, then an emergency stop and
    power on. Its partner while recording is the Python model (sim=None); the channel applies
    ``fault`` (LINK_FAULTS): random garbage bursts, frames cut short, every frame sent twice,
    the robot's replies lost at 20 % (so the host retransmits), or the port gone for 2 s
    mid-session.
    """
    from hexapod_bridge.link import RobotLink
    from hexapod_gait import preset, PRESETS

    if fault not in LINK_FAULTS:
        raise ValueError(f'unknown fault {fault!r}; known: {", ".join(LINK_FAULTS)}')
    rng = np.random.default_rng(seed)
    fuzzer = _Fuzzer(seed)
    gaits = [preset(name) for name in sorted(PRESETS)]
    gaits += [ext.gait_from_values(fuzzer._random_gait_values()) for _ in range(2)]
    script = Script()
    robot = RobotFirmware(now=0.0)
    link = RobotLink()
    t, step = 0.0, 0.004
    link.arm(True, t)

    def deliver(data: bytes) -> None:
        if fault == 'garbage' and rng.random() < 0.05:
            data = bytes(rng.integers(0, 256, int(rng.integers(1, 12)), dtype=np.uint8)) + data
        if fault == 'truncation' and rng.random() < 0.05 and len(data) > 1:
            data = data[: int(rng.integers(1, len(data)))]
        if fault == 'duplicates':
            data = data + data
        if fault == 'port_vanishes' and 6.0 <= t < 8.0:
            return  # the port is gone: nothing reaches the robot
        if data:
            ms = round(t * 1000)
            script.receive(ms, data)
            robot.receive(data, ms / 1000.0)

    def run(seconds: float) -> None:
        nonlocal t
        end = t + seconds
        while t < end:
            t += step
            for frame in link.poll(t):
                deliver(frame)
            ms = round(t * 1000)
            script.poll(ms)
            robot.receive(b'', ms / 1000.0)
            radio, _ = robot.advance(ms / 1000.0)
            if fault == 'lost_acks':
                radio = bytes(b for b in radio if rng.random() >= 0.02)
            link.receive(radio, t)

    for k, gait in enumerate(gaits):
        op = link.upload(gait)
        run(1.0)
        if op.ok:
            script.table()
            link.start_trial(1.0, op.result['gait_id'])
            run(0.5 if k == 1 else 1.6)
            if k == 1:
                link.stop_trial()
                run(0.5)
    link.emergency_stop()
    run(0.5)
    link.arm(True, t)
    link.motor_power(True)
    run(1.0)
    return script
