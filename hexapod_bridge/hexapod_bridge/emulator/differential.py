# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Differential tests of the C++ firmware module (firmware/) against the Python model.

A :class:`Script` of timed events (radio bytes arrive, the main loop polls, print the table) runs
through both: the model in-process (:func:`run_model`), the module through its sanitizer-built
``fw_replay`` tool (:func:`run_native`). Both print the same lines: the bytes sent and the state
after every event, the gait when it changes, the 120 Hz table and the servo targets (with the fold
of a leg with a dead servo) on request. :func:`compare` finds the first divergence; gait tables
and targets agree within the module's fixed-point units (TABLE_TOLERANCE).
:func:`fuzz_script` makes a seeded script of random frames: uploads of random gaits, every
command, legacy frames, duplicates, garbage, truncated and corrupted frames, gaps that trip the
failsafe. ``firmware_fuzz`` (CLI) runs one.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import math
import os
import struct
import subprocess
import time

from hexapod_bridge import extension as ext
from hexapod_bridge import legacy
from hexapod_bridge.emulator.firmware import FirmwareTiming, param_range, RobotFirmware
from hexapod_bridge.stream import HostParser
from hexapod_gait import from_genotype, GENOTYPE_SIZE
from hexapod_gait.parameters import from_omni_genotype, OMNI_GENOTYPE_SIZE
from hexapod_gait.trajectory import reachable_key_points
import numpy as np

#: Largest difference between the two gait tables: half the module's fixed-point unit (positions
#: 2e-4 rad, rates 1e-3 rad/s) plus float32 rounding.
TABLE_TOLERANCE = {'position': 1.0e-4 + 1e-6, 'velocity': 5.0e-4 + 1e-5}
#: The module stores joint rates in int16 units of 1e-3 rad/s: larger ones are clipped.
VELOCITY_LIMIT = 32.767


class FirmwareBuildMissing(FileNotFoundError):
    """The C++ module's host build (package hexapod_firmware) is not installed; says what to do."""


def firmware_prefix() -> str:
    """Return the install prefix of the hexapod_firmware package (the C++ module's host build)."""
    from ament_index_python.packages import get_package_prefix, PackageNotFoundError

    try:
        return get_package_prefix('hexapod_firmware')
    except PackageNotFoundError:
        raise FirmwareBuildMissing(
            'package hexapod_firmware is not built: run scripts/bootstrap.sh (colcon build)'
        ) from None


def replay_tool() -> str:
    """Return the path of the sanitizer-built fw_replay tool."""
    path = os.path.join(firmware_prefix(), 'lib', 'hexapod_firmware', 'fw_replay')
    if not os.access(path, os.X_OK):
        raise FirmwareBuildMissing(f'{path} is missing: rebuild package hexapod_firmware')
    return path


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


def _gait_values(gait) -> list[float]:
    return (
        [gait.body_velocity, gait.body_height, gait.period, gait.crab_angle]
        + [float(v) for f in ('radius', 'angle_offset', 'step_height') for v in getattr(gait, f)]
        + [float(v) for f in ('duty_factor', 'phase_offset') for v in getattr(gait, f)]
        + [float(gait.archive_index), gait.turn_rate]
    )


def run_model(script: Script) -> list[str]:
    """Run a script through the Python model; return its output lines (fw_replay's format)."""
    t = script.timing
    fw = RobotFirmware(
        walk_duration=t.walk_duration,
        failsafe_windows=t.failsafe_windows,
        telemetry_ticks=t.telemetry_ticks,
        ping_check_ticks=t.ping_check_ticks,
        now=script.start_ms / 1000.0,
        servo_ping=lambda servo: servo not in script.dead_servos,
        leg_map=script.leg_map,
    )
    lines: list[str] = []
    last = _gait_values(fw.gait)
    for event in script.events:
        if event[0] == 'S':
            targets = fw.servo_targets
            lines.append(
                f'S {targets.writes} ' + ' '.join(repr(float(v)) for v in targets.position)
            )
            continue
        if event[0] == 'T':
            table = fw.robot_table
            lines.append(f'T {len(table)}')
            lines.extend(
                ' '.join(repr(float(v)) for v in np.concatenate([p, v]))
                for p, v in zip(table.positions, table.velocities)
            )
            continue
        if event[0] == 'B':
            fw.receive(event[2], event[1] / 1000.0)
            radio = bytes(fw.out_radio)
            fw.out_radio.clear()
        else:
            radio, _ = fw.advance(event[1] / 1000.0)
        staged = sum(v is not None for v in fw.staged)
        lines.append(
            f'E {radio.hex() or "-"} {int(fw.walking)} {int(fw.estopped)} {int(fw.motors_on)}'
            f' {fw.gait_id} {staged} {fw._tick_count} {int(fw.trial_state)} {len(fw.robot_table)}'
        )
        values = _gait_values(fw.gait)
        if values != last:
            lines.append('G ' + ' '.join(repr(v) for v in values))
            last = values
    return lines


def run_native(script: Script, tool: str | None = None, timeout: float = 600.0) -> list[str]:
    """Run a script through the C++ module's fw_replay; return its output lines."""
    result = subprocess.run(
        [tool or replay_tool()],
        input=script.encode(),
        capture_output=True,
        timeout=timeout,
        check=False,
    )
    if result.returncode != 0:
        raise RuntimeError(
            f'fw_replay failed with exit status {result.returncode}:'
            f' {result.stderr.decode(errors="replace")[-4000:]}'
        )
    return result.stdout.decode().splitlines()


@dataclass(frozen=True)
class Divergence:
    """Where the module and the model first disagree (output line and event numbers)."""

    line: int
    event: int
    model: str
    native: str


@dataclass(frozen=True)
class Comparison:
    """The result of :func:`compare`: counts, and the first divergence if any."""

    events: int
    tables: int
    max_position_error: float
    max_velocity_error: float
    divergence: Divergence | None


def compare(model: list[str], native: list[str]) -> Comparison:
    """Compare two outputs line by line: exact; gaits by value, tables within tolerance."""
    events = tables = 0
    max_p = max_v = 0.0
    i = 0
    rows_left = 0

    def diverged(k: int) -> Comparison:
        a = model[k] if k < len(model) else '<end>'
        b = native[k] if k < len(native) else '<end>'
        return Comparison(events, tables, max_p, max_v, Divergence(k, events, a, b))

    while i < max(len(model), len(native)):
        if i >= len(model) or i >= len(native):
            return diverged(i)
        a, b = model[i], native[i]
        if rows_left:
            x = np.array(a.split(), dtype=float)
            y = np.array(b.split(), dtype=float)
            if x.shape != (36,) or y.shape != (36,):
                return diverged(i)
            dp = float(np.max(np.abs(x[:18] - y[:18])))
            dv = float(np.max(np.abs(np.clip(x[18:], -VELOCITY_LIMIT, VELOCITY_LIMIT) - y[18:])))
            max_p, max_v = max(max_p, dp), max(max_v, dv)
            if dp > TABLE_TOLERANCE['position'] or dv > TABLE_TOLERANCE['velocity']:
                return diverged(i)
            rows_left -= 1
        elif a.startswith('G ') and b.startswith('G '):
            if [float(v) for v in a.split()[1:]] != [float(v) for v in b.split()[1:]]:
                return diverged(i)
        elif a.startswith('S ') and b.startswith('S '):
            x, y = a.split()[1:], b.split()[1:]  # the writes, then 18 targets
            if len(x) != 19 or len(y) != 19 or x[0] != y[0]:
                return diverged(i)
            dp = float(np.max(np.abs(np.array(x[1:], float) - np.array(y[1:], float))))
            max_p = max(max_p, dp)
            if dp > TABLE_TOLERANCE['position']:
                return diverged(i)
        elif a.startswith('T ') and a == b:
            rows_left = int(a.split()[1])
            tables += 1
        elif a != b:
            return diverged(i)
        elif a.startswith('E '):
            events += 1
        i += 1
    return Comparison(events, tables, max_p, max_v, None)


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


@dataclass(frozen=True)
class FuzzResult:
    """One differential fuzz run: what it sent and whether the two firmwares agreed."""

    frames: int
    events: int
    tables: int
    commits_ok: int
    trials: int
    seconds: float
    max_position_error: float
    max_velocity_error: float
    divergence: Divergence | None


def _count_reports(lines: list[str]) -> tuple[int, int]:
    """Return (accepted COMMITs, started walks) in a model output."""
    parser, commits, walks = HostParser(), 0, 0
    for line in lines:
        if not line.startswith('E ') or line.split()[1] == '-':
            continue
        for frame in parser.feed(bytes.fromhex(line.split()[1])):
            if not isinstance(frame, ext.ReportFrame):
                continue
            if frame.type == ext.Report.ACK and frame.payload[:2] == bytes([ext.Cmd.COMMIT, 0]):
                commits += 1
            if frame.type == ext.Report.TRIAL and frame.payload[0] == ext.TrialState.WALKING:
                walks += 1
    return commits, walks


def fuzz(seed: int, frames: int, dead_servos: frozenset[int] = frozenset()) -> FuzzResult:
    """Run one seeded fuzz script through the model and the module and compare them."""
    t0 = time.monotonic()
    script = fuzz_script(seed, frames, dead_servos)
    model = run_model(script)
    native = run_native(script)
    result = compare(model, native)
    commits, walks = _count_reports(model)
    return FuzzResult(
        frames,
        result.events,
        result.tables,
        commits,
        walks,
        time.monotonic() - t0,
        result.max_position_error,
        result.max_velocity_error,
        result.divergence,
    )
