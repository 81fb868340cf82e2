# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The robot's firmware side of the radio protocol (legacy frames + extension v1).

For tests and the robot_emulator. Time is passed in explicitly, so it runs in real time over a
pseudo-terminal or faster in unit tests. Optionally drives a simulator (hexapod_sim's Simulator
interface, either engine) so the emulated robot really walks the gait it was sent, and emulates
the Xsens MTi (Xbus MTData at 100 Hz).

Firmware behaviour reproduced from robot-facts.md: a ~50 ms timer tick; telemetry every 10
ticks; a ping check every 50 ticks, and after ``failsafe_windows`` consecutive check windows
without a ping the walk stops; a walk lasts ``walk_duration`` (5 s) after a reset (movement
function 55) or START_TRIAL; valid movement frames are acknowledged with FF <checksum>.

Added with the firmware module (firmware/, issue 20), and specified by this model: the clock is
whole milliseconds (the firmware's HAL tick); bytes are taken one at a time, as the UART
interrupt takes them; a legacy movement that makes the gait unreachable is refused ("BAD
MOVEMENT"); and a servo health check pings the 18 servos between walks (at start-up, after every
walk, after HELLO; never while walking or with motor power off), reporting each one that does
not answer as ``FF FD 0B <servo id>``. The C++ module must produce the same bytes from the same
input: firmware/test and tests/test_firmware_native.py check it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
import math
import struct
from typing import Callable, Sequence

from hexapod_bridge.emulator.servo_targets import ServoTargets
from hexapod_bridge.protocol import extension as ext
from hexapod_bridge.protocol import legacy, xbus
from hexapod_bridge.protocol.stream import LegacyCommand, PingFrame, RobotReceiver
from hexapod_bridge.servos import SERVO_IDS, SERVO_PING_FAILED
from hexapod_gait import build_joint_table, preset, RANGES, ReachabilityError, ROBOT_RATE
from hexapod_gait.trajectory import POSE_TRANSITION_S, transition
from hexapod_sim.simulator import quat_to_euler, quat_to_matrix
import numpy as np

TICK = 0.05
#: VERSION's capability bits: bit 0, gait upload (extension v1).
CAPABILITIES = 1


@dataclass(frozen=True)
class FirmwareTiming:
    """The firmware's timing constants (robot-facts.md) and their defaults here."""

    walk_duration: float = 5.0  # s a walk lasts after a reset
    failsafe_windows: int = 11
    telemetry_ticks: int = 10
    ping_check_ticks: int = 50


def param_range(index: int) -> tuple[float, float]:
    """Return the inclusive range SET_PARAM accepts for parameter ``index`` (float32 value)."""
    name = ext.PARAM_NAMES[index].split('[')[0]
    return RANGES.get(name, (-1.0, 2.0**24))  # archive_index: -1 (none) or an index


def to_ms(now: float) -> int:
    """Return a time in seconds as the firmware's clock reads it: whole milliseconds."""
    return int(round(now * 1000.0))


@dataclass(frozen=True)
class ImuNoise:
    """Xsens-like errors: white noise, a constant accelerometer bias, orientation noise."""

    acc_sigma: float = 0.02  # m/s^2 per sample
    acc_bias: float = 0.03  # m/s^2, constant per axis (random sign/size up to this)
    gyro_sigma: float = 0.005  # rad/s
    euler_sigma: float = 0.3  # deg


class EmulatedImu:
    """An Xsens MTi on the simulated body: MTData samples at ``rate`` Hz, optionally noisy."""

    def __init__(self, rate: float = 100.0, noise: ImuNoise | None = None, seed: int = 0):
        self.rng = np.random.default_rng(seed)
        self.noise = noise
        self.acc_bias = (self.rng.uniform(-1, 1, 3) * noise.acc_bias) if noise else np.zeros(3)
        self.period = 1.0 / rate
        self._counter = 0
        self._velocity = np.zeros(3)

    def sample(self, sim) -> bytes:
        """Return one Xbus MTData message of the simulator's body now."""
        quat, gyro, _ = sim.imu()
        # An MTi filters internally: its output is the mean acceleration over the sample
        # interval, i.e. the change of velocity over it (point samples of the 240 Hz
        # finite difference would alias the foot-impact spikes).
        velocity = sim.base_velocity()[0]
        a_world = (velocity - self._velocity) / self.period
        self._velocity = velocity
        rot = quat_to_matrix(quat)
        acc = rot.T @ (a_world + np.array([0.0, 0.0, 9.81])) + self.acc_bias
        roll, pitch, yaw = (math.degrees(a) for a in quat_to_euler(quat))
        euler = np.array([roll, pitch, yaw])
        if self.noise is not None:
            acc = acc + self.rng.normal(0, self.noise.acc_sigma, 3)
            gyro = gyro + self.rng.normal(0, self.noise.gyro_sigma, 3)
            euler = euler + self.rng.normal(0, self.noise.euler_sigma, 3)
        euler[2] = (euler[2] + 180.0) % 360.0 - 180.0
        self._counter = (self._counter + 1) & 0xFFFF
        return xbus.encode_mtdata(
            xbus.MTData(
                tuple(acc),
                tuple(gyro),
                (0.0, 0.0, 0.0),
                tuple(float(v) for v in euler),
                self._counter,
            )
        )


@dataclass
class FirmwareStats:
    """Counters of the emulated firmware (pings, failsafe trips, frames, duplicates)."""

    pings: int = 0
    failsafe_trips: int = 0
    missed_windows: int = 0
    frames: int = 0
    duplicates: int = 0


@dataclass
class TrialRecord:
    """
    One walk of the emulated robot, with the true displacement for tests.

    The distance is measured along the gait's walking direction in the frame the robot started
    the walk in (its heading then, plus the crab angle), the frame of the bridge's odometry and
    of a simulated evaluation, which starts every gait heading along x.
    """

    gait_id: int
    crab_angle: float
    duration: float
    start_position: np.ndarray
    start_yaw: float = 0.0  # heading when the walk started [rad]
    end_position: np.ndarray | None = None
    state: str = 'walking'

    def summary(self) -> dict:
        """Return the walk as a dict: gait id, end state, duration, distance and speed."""
        d = (
            (self.end_position - self.start_position)[:2]
            if self.end_position is not None
            else np.zeros(2)
        )
        heading = self.start_yaw + self.crab_angle
        distance = float(d[0] * math.cos(heading) + d[1] * math.sin(heading))
        return {
            'gait_id': self.gait_id,
            'state': self.state,
            'duration': self.duration,
            'distance': distance,
            'speed': distance / self.duration,
        }


class RobotFirmware:
    """The robot's firmware side of the radio protocol, in emulated time (module docstring)."""

    def __init__(
        self,
        sim=None,
        walk_duration: float = FirmwareTiming.walk_duration,
        failsafe_windows: int = FirmwareTiming.failsafe_windows,
        telemetry_ticks: int = FirmwareTiming.telemetry_ticks,
        ping_check_ticks: int = FirmwareTiming.ping_check_ticks,
        imu_rate: float = 100.0,
        imu_noise: ImuNoise | None = None,
        seed: int = 0,
        now: float = 0.0,
        servo_ping: Callable[[int], bool] | None = None,
        leg_map: Sequence[int] = ext.IDENTITY_LEG_MAP,
    ) -> None:
        self.receiver = RobotReceiver()
        # the robot's leg number of each URDF leg (bridge_node's leg_map): per-leg values and
        # servos are in the robot's slots; the legs' geometry, and the simulator, are the URDF's
        self.leg_map = ext.validate_leg_map(leg_map)
        # the health check's hook: does servo <id> answer a ping? (None: every servo answers)
        self.servo_ping = servo_ping or (lambda servo: True)
        self._health_pending = True  # at start-up
        self.sim = sim
        self.walk_duration = walk_duration
        self.failsafe_windows = failsafe_windows
        self.telemetry_ticks = telemetry_ticks
        self.ping_check_ticks = ping_check_ticks
        self.stats = FirmwareStats()
        self.imu = EmulatedImu(imu_rate, imu_noise, seed)
        # the gait in the robot's slots: at first the firmware's hard-coded tripod
        self.gait = ext.gait_in_slots(preset('control'), self.leg_map)
        self.gait_id = 0
        # the gait table at the robot's 120 Hz in its slots (the firmware's own; the sim plays its
        # own rate)
        self.robot_table = self._check_reachable(self.gait)
        self.staged: list[float | None] = [None] * ext.N_PARAMS
        self.motors_on = True
        self.estopped = False
        self.walking = False
        self.walk_end = 0.0
        self.trial_seq = 0
        self.trial_state = ext.TrialState.IDLE  # of the last TRIAL report
        self.trials: list[TrialRecord] = []
        self._recent: dict[tuple[int, int], bytes] = {}  # (type, seq) -> ack sent
        self._tick_count = 0
        self._now_ms = to_ms(now)
        self._next_tick_ms = self._now_ms
        self._walk_start_ms = self._walk_end_ms = 0
        self._pings_in_window = 0
        self._missed = 0
        self._sim_time = now
        self._next_imu = now
        self._table = None
        self._row = 0
        self._hold_row = None  # prepared rows of the poses to stand in (the last one is held)
        self._hold_count = 0
        self._hold_index = 0
        self.out_radio = bytearray()
        self.out_imu = bytearray()
        # what the C++ module writes to the servos (the differential tests compare them)
        self.servo_targets = ServoTargets(self.robot_table.positions[0])
        if sim is not None:
            self._table = self._sim_table()
            sim.reset(self._table.positions[0])
            self._load_table()

    @property
    def resyncs(self) -> int:
        """Return how often the receiver slid to find the next frame."""
        return self.receiver.stats.resyncs

    # -- receiving ---------------------------------------------------------------------------
    def receive(self, data: bytes, now: float) -> None:
        """Bytes from the radio at time ``now``: parse frames and act on them, byte by byte."""
        self._now_ms = to_ms(now)
        for byte in data:
            for frame in self.receiver.feed(bytes((byte,))):
                self._on_frame(frame, now)

    def _on_frame(self, frame, now: float) -> None:
        self.stats.frames += 1
        if isinstance(frame, PingFrame):
            self.stats.pings += 1
            self._pings_in_window += 1
            self.out_radio += bytes([0xFF, 0xFA])
        elif isinstance(frame, legacy.Movement):
            self.out_radio += legacy.encode_ack(self.receiver.last_checksum)
            self._on_movement(frame, now)
        elif isinstance(frame, LegacyCommand):
            self._on_legacy_command(frame, now)
        elif isinstance(frame, ext.CommandFrame):
            self._on_extension(frame, now)

    def _on_movement(self, m: legacy.Movement, now: float) -> None:
        if m.function == legacy.Function.RESET:
            self.out_radio += legacy.encode_text('RESET')
            self.start_walk(now, self.walk_duration)
        elif m.function == legacy.Function.STAND or m.direction == legacy.Direction.STOP:
            self._stop_walk('stopped')
        elif m.function == legacy.Function.WALK and m.direction in legacy.DIRECTION_ANGLE:
            try:
                gait = self.gait.replace(
                    body_velocity=m.speed,
                    body_height=m.height_mm / 1000.0,
                    crab_angle=legacy.DIRECTION_ANGLE[legacy.Direction(m.direction)],
                )
                table = self._check_reachable(gait)
            except ValueError:  # out of range, or unreachable: the gait is kept
                self.out_radio += legacy.encode_text('BAD MOVEMENT')
                return
            self.gait, self.robot_table = gait, table
            self.servo_targets.gait_loaded(self.walking)
            self._load_table()

    def _on_legacy_command(self, cmd: LegacyCommand, now: float) -> None:
        if cmd.code == 0xDD:
            period = struct.unpack('<f', cmd.raw[2:6])[0]
            if math.isfinite(period) and 0.05 <= period <= 60.0:
                self.telemetry_ticks = max(1, int(round(period / TICK)))
        if cmd.code == 0xFA:
            self.motors_on = bool(cmd.raw[2])
            if self.motors_on:
                self.estopped = False
            else:
                self._stop_walk('stopped')

    def _ack(self, frame: ext.CommandFrame, status: ext.Status, value: int = 0) -> None:
        ack = ext.encode_report(
            ext.Report.ACK,
            frame.seq,
            bytes([frame.type, int(status)]) + struct.pack('>H', value & 0xFFFF),
        )
        self._recent[(frame.type, frame.seq)] = ack
        if len(self._recent) > 64:
            self._recent.pop(next(iter(self._recent)))
        self.out_radio += ack

    def _on_extension(self, f: ext.CommandFrame, now: float) -> None:
        repeat = self._recent.get((f.type, f.seq))
        if repeat is not None and f.type != ext.Cmd.ESTOP:
            self.stats.duplicates += 1  # a retransmission: answer again, apply once
            self.out_radio += repeat
            return
        if f.type == ext.Cmd.SET_PARAM:
            index = f.payload[0]
            if index >= ext.N_PARAMS:
                return self._ack(f, ext.Status.BAD_INDEX, index)
            value = struct.unpack('<f', f.payload[1:5])[0]
            lo, hi = param_range(index)
            if not (math.isfinite(value) and lo <= value <= hi):
                return self._ack(f, ext.Status.OUT_OF_RANGE, index)
            self.staged[index] = value
            return self._ack(f, ext.Status.OK, index)
        if f.type == ext.Cmd.COMMIT:
            count, set_crc, gait_id = f.payload[0], *struct.unpack('>HH', f.payload[1:5])
            if count != ext.N_PARAMS or any(v is None for v in self.staged):
                return self._ack(f, ext.Status.SET_INCOMPLETE, gait_id)
            if ext.values_crc(self.staged) != set_crc:
                return self._ack(f, ext.Status.SET_CRC_MISMATCH, gait_id)
            if self.walking:
                return self._ack(f, ext.Status.BUSY, gait_id)
            try:
                gait = ext.gait_from_values(self.staged)
                table = self._check_reachable(gait)
            except ReachabilityError:
                self.out_radio += legacy.encode_text('GAIT REJECTED')
                return self._ack(f, ext.Status.UNREACHABLE, gait_id)
            except ValueError:
                self.out_radio += legacy.encode_text('GAIT REJECTED')
                return self._ack(f, ext.Status.OUT_OF_RANGE, gait_id)
            self.gait, self.gait_id, self.robot_table = gait, gait_id, table
            self.servo_targets.gait_loaded(self.walking)
            self.staged = [None] * ext.N_PARAMS
            self._load_table()
            return self._ack(f, ext.Status.OK, gait_id)
        if f.type == ext.Cmd.START_TRIAL:
            ms, gait_id, _flags = struct.unpack('>HHB', f.payload)
            if self.estopped or not self.motors_on:
                return self._ack(f, ext.Status.ESTOPPED, gait_id)
            if gait_id != self.gait_id:
                return self._ack(f, ext.Status.NO_GAIT, gait_id)
            if self.walking:
                return self._ack(f, ext.Status.BUSY, gait_id)
            self._ack(f, ext.Status.OK, gait_id)
            self.start_walk(now, ms / 1000.0)
            return None
        if f.type == ext.Cmd.STOP_TRIAL:
            self._ack(f, ext.Status.OK)
            self._stop_walk('stopped')
            return None
        if f.type == ext.Cmd.ESTOP:
            self.estopped, self.motors_on = True, False
            self._stop_walk('estopped')
            self._ack(f, ext.Status.OK)
            return None
        if f.type == ext.Cmd.HELLO:
            self.out_radio += ext.encode_report(
                ext.Report.VERSION,
                f.seq,
                bytes([ext.PROTOCOL_MAJOR, ext.PROTOCOL_MINOR]) + struct.pack('>H', CAPABILITIES),
            )
            self._health_pending = True  # a host that says hello hears of every dead servo
            return None
        return self._ack(f, ext.Status.UNKNOWN_TYPE)

    def _check_reachable(self, gait):
        """
        Return the table at 120 Hz of a gait in the robot's slots, its joints in the slots too.

        The firmware's own IK check (raises its errors): each slot's leg where it is mounted.
        """
        urdf = build_joint_table(ext.gait_in_urdf_order(gait, self.leg_map), rate=ROBOT_RATE)
        return replace(
            urdf,
            positions=ext.joints_in_slots(urdf.positions, self.leg_map),
            velocities=ext.joints_in_slots(urdf.velocities, self.leg_map),
            stance=urdf.stance[:, ext.urdf_legs_of_slots(self.leg_map)],
        )

    def _sim_table(self):
        """Return the gait's table at the simulator's rate, in the URDF's joint order."""
        gait = ext.gait_in_urdf_order(self.gait, self.leg_map)
        return build_joint_table(gait, rate=1.0 / self.sim.dt)

    # -- walking -----------------------------------------------------------------------------
    def _load_table(self) -> None:
        if self.sim is not None:
            self._table = self._sim_table()
            self._rows = self.sim.prepare_rows(self._table.positions, self._table.velocities)
            if not self.walking:
                # standing between walks, a new gait's first pose is reached first, so every walk
                # starts from its gait's own first pose, as a simulated evaluation does
                self._stand(self._table.positions[0], POSE_TRANSITION_S)

    def _stand(self, pose: np.ndarray, within: float) -> None:
        """Move the legs from where they are to ``pose`` in ``within`` s, then hold it."""
        path = transition(self.sim.joint_states()[0], pose, within, 1.0 / self.sim.dt)
        self._hold_row = self.sim.prepare_rows(path, np.zeros_like(path))
        self._hold_count, self._hold_index = len(path), 0

    def start_walk(self, now: float, duration: float) -> None:
        """Walk the current gait for ``duration`` s from ``now`` (as reset and START_TRIAL do)."""
        self._walk_start_ms = to_ms(now)
        self._walk_end_ms = self._walk_start_ms + to_ms(duration)
        self.walking, self.walk_end = True, self._walk_end_ms / 1000.0
        self._row = 0
        self.servo_targets.walk_started()
        position = self.sim.base_pose()[0] if self.sim is not None else np.zeros(3)
        yaw = self.sim.base_euler()[2] if self.sim is not None else 0.0
        self.trials.append(
            TrialRecord(self.gait_id, self.gait.crab_angle, duration, position, float(yaw))
        )
        self._trial_report(ext.TrialState.WALKING, self._walk_start_ms)

    def _stop_walk(self, state: str) -> None:
        if not self.walking:
            return
        self.walking = False
        self._health_pending = True
        if self.trials:
            record = self.trials[-1]
            record.state = state
            record.end_position = self.sim.base_pose()[0] if self.sim is not None else np.zeros(3)
        if self.sim is not None and self._table is not None:
            # stand still in the pose the walk stopped in
            self._stand(self._table.positions[self._row % len(self._table)], 0.0)
        state_code = {
            'done': ext.TrialState.DONE,
            'stopped': ext.TrialState.STOPPED,
            'estopped': ext.TrialState.ESTOPPED,
            'failsafe': ext.TrialState.FAILSAFE,
        }[state]
        self._trial_report(state_code, self._walk_end_ms if state == 'done' else self._now_ms)

    def _trial_report(self, state: ext.TrialState, now_ms: int) -> None:
        elapsed = max(0, now_ms - self._walk_start_ms)
        self.trial_state = state
        self.trial_seq = (self.trial_seq + 1) & 0xFF
        self.out_radio += ext.encode_report(
            ext.Report.TRIAL,
            self.trial_seq,
            bytes([int(state)]) + min(elapsed, 0xFFFFFF).to_bytes(3, 'big'),
        )

    # -- time ----------------------------------------------------------------------------------
    def advance(self, now: float) -> tuple[bytes, bytes]:
        """Run timers, the walk and the simulation up to ``now``; return (radio, imu) bytes."""
        self._now_ms = now_ms = to_ms(now)
        while self._next_tick_ms <= now_ms:
            self._timer_tick()
            self._next_tick_ms += to_ms(TICK)
        if self.sim is not None:
            self._step_sim(now)
        elif self.walking and now_ms >= self._walk_end_ms:
            self._stop_walk('done')
        self.servo_targets.update(
            now_ms, self.walking, self._walk_start_ms, self.robot_table.positions
        )
        radio, imu = bytes(self.out_radio), bytes(self.out_imu)
        self.out_radio.clear()
        self.out_imu.clear()
        return radio, imu

    def _timer_tick(self) -> None:
        self._tick_count += 1
        if self._tick_count % self.telemetry_ticks == 0:
            pitch, roll, yaw = self._attitude()
            self.out_radio += legacy.encode_telemetry(
                legacy.Telemetry(float(self._tick_count), pitch, roll, yaw, 0.0, 0.0)
            )
        if self._tick_count % self.ping_check_ticks == 0:
            if self._pings_in_window == 0:
                self._missed += 1
                self.stats.missed_windows += 1
            else:
                self._missed = 0
            self._pings_in_window = 0
            if self._missed >= self.failsafe_windows and self.walking:
                self.stats.failsafe_trips += 1
                self._stop_walk('failsafe')
        if self._health_pending and not self.walking and self.motors_on:
            self._health_check()

    def _health_check(self) -> None:
        """Ping every servo; report each one that does not answer (FF FD 0B <servo id>)."""
        self._health_pending = False
        dead = frozenset(servo for servo in SERVO_IDS if not self.servo_ping(servo))
        for servo in sorted(dead):
            self.out_radio += legacy.encode_error(SERVO_PING_FAILED, servo)
        self.servo_targets.health_checked(dead, self.robot_table.positions[0])

    def _attitude(self) -> tuple[float, float, float]:
        if self.sim is None:
            return 0.0, 0.0, 0.0
        roll, pitch, yaw = self.sim.base_euler()
        return pitch, roll, yaw

    def _step_sim(self, now: float) -> None:
        sim = self.sim
        while self._sim_time + sim.dt <= now:
            if self.walking and self._sim_time >= self.walk_end - 1e-9:
                self._stop_walk('done')
            if self.walking:
                row = self._row % len(self._table)
                sim.apply_row(self._rows, row)
                self._row += 1
            elif self._hold_row is not None:
                sim.apply_row(self._hold_row, min(self._hold_index, self._hold_count - 1))
                self._hold_index += 1
            sim.set_motor_power(self.motors_on)
            sim.step()
            sim.update_imu()
            self._sim_time += sim.dt
            if self._sim_time >= self._next_imu - 1e-9:
                self._next_imu += self.imu.period
                self.out_imu += self.imu.sample(sim)
