# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The C++ firmware module (firmware/) in the robot emulator: ``robot_emulator --firmware native``.

:class:`NativeFirmware` loads the module's host build (libhexapod_fw.so of package
hexapod_firmware) through ctypes and gives it its hooks. :class:`NativeRobotFirmware` puts it where
the emulator's Python model sits: same interface (receive, advance, trials, stats), the same
simulated body and IMU, but every protocol decision, the gait table and the servo targets come
from the C++ module. Its clock is the simulation's, in whole milliseconds; its servo targets (at
most 120 Hz) are held between writes, as a Dynamixel holds its goal.
"""

from __future__ import annotations

import ctypes
import os
from typing import Callable, Sequence

from hexapod_bridge.emulator.differential import firmware_prefix, FirmwareBuildMissing
from hexapod_bridge.emulator.firmware import (
    EmulatedImu,
    FirmwareStats,
    FirmwareTiming,
    ImuNoise,
    to_ms,
    TrialRecord,
)
from hexapod_bridge.protocol import extension as ext
import numpy as np

N_JOINTS = 18

_RADIO_WRITE = ctypes.CFUNCTYPE(
    None, ctypes.c_void_p, ctypes.POINTER(ctypes.c_uint8), ctypes.c_uint32
)
_SERVO_WRITE = ctypes.CFUNCTYPE(
    None, ctypes.c_void_p, ctypes.POINTER(ctypes.c_float), ctypes.POINTER(ctypes.c_float)
)
_SERVO_PING = ctypes.CFUNCTYPE(ctypes.c_uint8, ctypes.c_void_p, ctypes.c_uint8)
_MOTOR_POWER = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_uint8)
_ATTITUDE = ctypes.CFUNCTYPE(
    None,
    ctypes.c_void_p,
    ctypes.POINTER(ctypes.c_float),
    ctypes.POINTER(ctypes.c_float),
    ctypes.POINTER(ctypes.c_float),
)


class _Hooks(ctypes.Structure):
    _fields_ = [
        ('ctx', ctypes.c_void_p),
        ('radio_write', _RADIO_WRITE),
        ('servo_write', _SERVO_WRITE),
        ('servo_ping', _SERVO_PING),
        ('motor_power', _MOTOR_POWER),
        ('attitude', _ATTITUDE),
    ]


class NativeState(ctypes.Structure):
    """The module's hx_state (include/hexapod_fw/hexapod_fw.h)."""

    _fields_ = (
        [
            (name, ctypes.c_uint8)
            for name in ('walking', 'estopped', 'motors_on', 'trial_state', 'trial_seq', 'staged')
        ]
        + [('gait_id', ctypes.c_uint16), ('table_rows', ctypes.c_uint16)]
        + [
            (name, ctypes.c_uint32)
            for name in (
                'tick_count',
                'walk_start_ms',
                'walk_end_ms',
                'frames',
                'pings',
                'duplicates',
                'failsafe_trips',
                'missed_windows',
                'checksum_errors',
                'resyncs',
                'bytes_dropped',
            )
        ]
    )


def library_path() -> str:
    """Return the path of the module's shared library (package hexapod_firmware)."""
    path = os.path.join(firmware_prefix(), 'lib', 'libhexapod_fw.so')
    if not os.path.exists(path):
        raise FirmwareBuildMissing(f'{path} is missing: rebuild package hexapod_firmware')
    return path


def _load(path: str) -> ctypes.CDLL:
    lib = ctypes.CDLL(path)
    lib.hx_size.restype = ctypes.c_size_t
    lib.hx_init.argtypes = [
        ctypes.c_void_p,
        ctypes.c_size_t,
        ctypes.POINTER(_Hooks),
        ctypes.c_uint32,
        ctypes.c_uint16,
        ctypes.c_uint16,
        ctypes.c_uint16,
        ctypes.POINTER(ctypes.c_uint8),
        ctypes.c_uint32,
    ]
    lib.hx_init.restype = ctypes.c_int
    lib.hx_receive.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_size_t, ctypes.c_uint32]
    lib.hx_poll.argtypes = [ctypes.c_void_p, ctypes.c_uint32]
    lib.hx_get_state.argtypes = [ctypes.c_void_p, ctypes.POINTER(NativeState)]
    lib.hx_gait.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_double)]
    lib.hx_table_row.argtypes = [
        ctypes.c_void_p,
        ctypes.c_int,
        ctypes.POINTER(ctypes.c_float),
        ctypes.POINTER(ctypes.c_float),
    ]
    lib.hx_table_row.restype = ctypes.c_int
    return lib


class NativeFirmware:
    """
    One instance of the C++ module, driven from Python.

    ``servo_ping`` answers the health check's pings; ``attitude`` (pitch, roll, yaw) feeds the
    telemetry. Radio bytes the module sends collect in ``out_radio``; the last servo targets are
    ``position`` and ``velocity`` (18 joints), with ``servo_writes`` counting the writes.
    """

    def __init__(
        self,
        timing: FirmwareTiming = FirmwareTiming(),
        now_ms: int = 0,
        servo_ping: Callable[[int], bool] | None = None,
        attitude: Callable[[], tuple[float, float, float]] | None = None,
        library: str | None = None,
        leg_map: Sequence[int] = ext.IDENTITY_LEG_MAP,
    ) -> None:
        self._lib = _load(library or library_path())
        self.leg_map = ext.validate_leg_map(leg_map)
        self.out_radio = bytearray()
        self.position = np.zeros(N_JOINTS)
        self.velocity = np.zeros(N_JOINTS)
        self.servo_writes = 0
        self.motor_power: bool = True
        self._servo_ping = servo_ping or (lambda servo: True)
        self._attitude = attitude

        # ctypes callbacks must stay referenced as long as the module may call them
        def radio_write(_ctx, data, n):
            self.out_radio += ctypes.string_at(data, n)

        def servo_write(_ctx, position, velocity):
            self.position = np.ctypeslib.as_array(position, (N_JOINTS,)).astype(float)
            self.velocity = np.ctypeslib.as_array(velocity, (N_JOINTS,)).astype(float)
            self.servo_writes += 1

        def ping(_ctx, servo):
            return 1 if self._servo_ping(int(servo)) else 0

        def motor_power(_ctx, on):
            self.motor_power = bool(on)

        def attitude_hook(_ctx, pitch, roll, yaw):
            p, r, y = self._attitude()
            pitch[0], roll[0], yaw[0] = p, r, y

        self._callbacks = (
            _RADIO_WRITE(radio_write),
            _SERVO_WRITE(servo_write),
            _SERVO_PING(ping),
            _MOTOR_POWER(motor_power),
            _ATTITUDE(attitude_hook) if attitude is not None else _ATTITUDE(),
        )
        self._hooks = _Hooks(None, *self._callbacks)
        size = int(self._lib.hx_size())
        self._memory = (ctypes.c_uint64 * ((size + 7) // 8))()  # 8-byte aligned, owned here
        status = self._lib.hx_init(
            self._memory,
            ctypes.sizeof(self._memory),
            ctypes.byref(self._hooks),
            to_ms(timing.walk_duration),
            timing.failsafe_windows,
            timing.telemetry_ticks,
            timing.ping_check_ticks,
            (ctypes.c_uint8 * 6)(*self.leg_map),
            now_ms & 0xFFFFFFFF,
        )
        if status != 0:
            raise ValueError(f'the firmware module refused its configuration {timing}')

    def receive(self, data: bytes, now_ms: int) -> None:
        """Radio bytes arrive at ``now_ms``."""
        self._lib.hx_receive(self._memory, bytes(data), len(data), now_ms & 0xFFFFFFFF)

    def poll(self, now_ms: int) -> None:
        """Poll the module from the main loop at ``now_ms``."""
        self._lib.hx_poll(self._memory, now_ms & 0xFFFFFFFF)

    def state(self) -> NativeState:
        """Return the module's state and counters."""
        state = NativeState()
        self._lib.hx_get_state(self._memory, ctypes.byref(state))
        return state

    def gait(self) -> list[float]:
        """Return the gait in use: the protocol's 36 values."""
        values = (ctypes.c_double * ext.N_PARAMS)()
        self._lib.hx_gait(self._memory, values)
        return list(values)

    def table(self) -> tuple[np.ndarray, np.ndarray]:
        """Return the module's 120 Hz gait table: positions and rates, (rows, 18) each."""
        rows = self.state().table_rows
        positions, velocities = np.zeros((rows, N_JOINTS)), np.zeros((rows, N_JOINTS))
        p, v = (ctypes.c_float * N_JOINTS)(), (ctypes.c_float * N_JOINTS)()
        for row in range(rows):
            self._lib.hx_table_row(self._memory, row, p, v)
            positions[row], velocities[row] = list(p), list(v)
        return positions, velocities


_TRIAL_STATES = {
    ext.TrialState.DONE: 'done',
    ext.TrialState.STOPPED: 'stopped',
    ext.TrialState.ESTOPPED: 'estopped',
    ext.TrialState.FAILSAFE: 'failsafe',
}


class NativeRobotFirmware:
    """The emulated robot with the C++ module as its firmware (module docstring)."""

    def __init__(
        self,
        sim=None,
        timing: FirmwareTiming = FirmwareTiming(),
        imu_rate: float = 100.0,
        imu_noise: ImuNoise | None = None,
        seed: int = 0,
        now: float = 0.0,
        servo_ping: Callable[[int], bool] | None = None,
        leg_map: Sequence[int] = ext.IDENTITY_LEG_MAP,
    ) -> None:
        self.sim = sim
        self.imu = EmulatedImu(imu_rate, imu_noise, seed)
        self.trials: list[TrialRecord] = []
        self.out_imu = bytearray()
        self._sim_time = now
        self._next_imu = now
        self._rows = None
        self._walking = False
        self.firmware = NativeFirmware(
            timing,
            to_ms(now),
            servo_ping,
            attitude=self._attitude if sim is not None else None,
            leg_map=leg_map,
        )
        if sim is not None:  # the body starts in the pose the firmware wrote at start-up
            sim.reset(self._urdf(self.firmware.position))
            self._hold_targets()

    @property
    def stats(self) -> FirmwareStats:
        """Return the module's counters, as the Python model's."""
        s = self.firmware.state()
        return FirmwareStats(s.pings, s.failsafe_trips, s.missed_windows, s.frames, s.duplicates)

    @property
    def resyncs(self) -> int:
        """Return how often the module's receiver slid to find the next frame."""
        return self.firmware.state().resyncs

    def _attitude(self) -> tuple[float, float, float]:
        roll, pitch, yaw = self.sim.base_euler()
        return pitch, roll, yaw

    def _clock(self, now: float) -> int:
        # with a body, the firmware's clock is the simulation's (it trails ``now`` by < 1 step)
        return to_ms(self._sim_time if self.sim is not None else now)

    def receive(self, data: bytes, now: float) -> None:
        """Bytes from the radio at time ``now``."""
        self.firmware.receive(data, self._clock(now))
        self._note_walk()

    def advance(self, now: float) -> tuple[bytes, bytes]:
        """Run the module and the simulation up to ``now``; return (radio, imu) bytes."""
        if self.sim is None:
            self.firmware.poll(to_ms(now))
            self._note_walk()
        else:
            self._step_sim(now)
        radio, imu = bytes(self.firmware.out_radio), bytes(self.out_imu)
        self.firmware.out_radio.clear()
        self.out_imu.clear()
        return radio, imu

    def _step_sim(self, now: float) -> None:
        sim = self.sim
        while self._sim_time + sim.dt <= now:
            writes = self.firmware.servo_writes
            self.firmware.poll(to_ms(self._sim_time))
            self._note_walk()
            if self.firmware.servo_writes != writes:
                self._hold_targets()
            sim.apply_row(self._rows, 0)
            sim.set_motor_power(self.firmware.motor_power)
            sim.step()
            sim.update_imu()
            self._sim_time += sim.dt
            if self._sim_time >= self._next_imu - 1e-9:
                self._next_imu += self.imu.period
                self.out_imu += self.imu.sample(sim)

    def _hold_targets(self) -> None:
        self._rows = self.sim.prepare_rows(
            self._urdf(self.firmware.position)[None, :],
            self._urdf(self.firmware.velocity)[None, :],
        )

    def _urdf(self, joints: np.ndarray) -> np.ndarray:
        """Return the module's servo values (the robot's slots) in the simulator's URDF order."""
        return ext.joints_in_urdf_order(joints, self.firmware.leg_map)

    def _note_walk(self) -> None:
        """Keep a TrialRecord of every walk the module starts and ends (the simulator's truth)."""
        state = self.firmware.state()
        walking = bool(state.walking)
        if walking and not self._walking:
            gait = self.firmware.gait()  # (its crab angle does not depend on the leg order)
            position = self.sim.base_pose()[0] if self.sim is not None else np.zeros(3)
            yaw = float(self.sim.base_euler()[2]) if self.sim is not None else 0.0
            duration = ((state.walk_end_ms - state.walk_start_ms) & 0xFFFFFFFF) / 1000.0
            self.trials.append(TrialRecord(state.gait_id, gait[3], duration, position, yaw))
        elif self._walking and not walking and self.trials:
            record = self.trials[-1]
            record.state = _TRIAL_STATES.get(ext.TrialState(state.trial_state), 'stopped')
            record.end_position = self.sim.base_pose()[0] if self.sim is not None else np.zeros(3)
        self._walking = walking
