# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Gait-upload extension of the radio protocol, version 1 (specification: docs/radio-protocol.md).

Every frame is 10 bytes, so PC -> robot frames fit the robot's fixed 10-byte receive path, and
each carries a CRC-16/CCITT-FALSE (over bytes 0..7, big-endian in bytes 8..9) and a sequence
number. The marker 0xE7 is not a legacy first byte (0x01 movement, 0x37 ping, 0xFF command).

PC -> robot:   E7 type seq p0 p1 p2 p3 p4 crc_hi crc_lo
  SET_PARAM    p0 = parameter index (PARAM_NAMES), p1..p4 = float32 LE value
  COMMIT       p0 = parameter count, p1..p2 = CRC-16 of the staged values (index order,
               float32 LE bytes), p3..p4 = gait id (uint16 BE): apply the staged set atomically
  START_TRIAL  p0..p1 = duration [ms] (uint16 BE), p2..p3 = gait id, p4 = flags (bit 0: stand
               first): walk the committed gait for the duration, then stop
  STOP_TRIAL   stop walking now
  ESTOP        stop walking and cut motor power until a new START_TRIAL after motor power on
  HELLO        p0 = host protocol version; the robot answers VERSION
Robot -> PC:   FF E7 type seq p0 p1 p2 p3 crc_hi crc_lo   (seq echoes the request's)
  ACK          p0 = acknowledged type, p1 = status (Status), p2..p3 = gait id or parameter index
  TRIAL        p0 = TrialState, p1..p3 = elapsed ms (uint24 BE); seq counts the robot's reports
  VERSION      p0 = major, p1 = minor, p2..p3 = capability bits
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum
import math
import struct
from typing import Sequence

from hexapod_bridge.protocol.crc import crc16
from hexapod_gait import GaitParameters, RANGES
from hexapod_gait import ROBOT_RATE as ROBOT_TABLE_RATE
from hexapod_gait.parameters import LEG_FIELDS
import numpy as np

MARKER = 0xE7
FRAME_LEN = 10
PROTOCOL_MAJOR, PROTOCOL_MINOR = 1, 1  # 1.1: parameter 35, the turn rate

PARAM_NAMES: tuple[str, ...] = (
    ('body_velocity', 'body_height', 'period', 'crab_angle')
    + tuple(
        f'{field}[{leg}]'
        for field in ('radius', 'angle_offset', 'step_height', 'duty_factor', 'phase_offset')
        for leg in range(1, 7)
    )
    + ('archive_index', 'turn_rate')
)
N_PARAMS = len(PARAM_NAMES)  # 36


class Cmd(IntEnum):
    """Host -> robot command types of extension v1."""

    SET_PARAM = 0x10
    COMMIT = 0x11
    START_TRIAL = 0x12
    STOP_TRIAL = 0x13
    ESTOP = 0x14
    HELLO = 0x15


class Report(IntEnum):
    """Robot -> host report types of extension v1."""

    ACK = 0x01
    TRIAL = 0x02
    VERSION = 0x03


class Status(IntEnum):
    """Result codes in the robot's ACK of a command."""

    OK = 0
    BAD_INDEX = 1
    OUT_OF_RANGE = 2
    SET_INCOMPLETE = 3
    SET_CRC_MISMATCH = 4
    BUSY = 5
    NO_GAIT = 6
    ESTOPPED = 7
    UNKNOWN_TYPE = 8
    UNREACHABLE = 9


class TrialState(IntEnum):
    """Trial states in the robot's TRIAL reports."""

    IDLE = 0
    WALKING = 1
    DONE = 2
    STOPPED = 3
    ESTOPPED = 4
    FAILSAFE = 5


@dataclass(frozen=True)
class CommandFrame:
    """A decoded PC -> robot extension frame."""

    type: int  # noqa: A003 (the frame field named in the protocol)
    seq: int
    payload: bytes  # 5 bytes


@dataclass(frozen=True)
class ReportFrame:
    """A decoded robot -> PC extension frame."""

    type: int  # noqa: A003 (the frame field named in the protocol)
    seq: int
    payload: bytes  # 4 bytes


class ExtensionError(ValueError):
    """A value cannot be sent in an extension frame; the message says why."""

    pass


def _seal(body: bytes) -> bytes:
    return body + struct.pack('>H', crc16(body))


def encode_command(kind: Cmd, seq: int, payload: bytes = b'') -> bytes:
    """Return a 10-byte host -> robot extension frame (CRC-16 sealed)."""
    if len(payload) > 5:
        raise ExtensionError('command payload is at most 5 bytes')
    return _seal(bytes([MARKER, int(kind), seq & 0xFF]) + payload.ljust(5, b'\0'))


def encode_report(kind: Report, seq: int, payload: bytes = b'') -> bytes:
    """Return a robot -> host extension report frame (CRC-16 sealed)."""
    if len(payload) > 4:
        raise ExtensionError('report payload is at most 4 bytes')
    return _seal(bytes([0xFF, MARKER, int(kind), seq & 0xFF]) + payload.ljust(4, b'\0'))


def crc_ok(frame: bytes | bytearray) -> bool:
    """Return True if a frame's trailing CRC-16 matches its body."""
    return len(frame) == FRAME_LEN and struct.unpack('>H', bytes(frame[8:10]))[0] == crc16(
        frame[:8]
    )


def decode_command(frame: bytes | bytearray) -> CommandFrame:
    """Decode a 10-byte host -> robot frame; ExtensionError if it is not a command."""
    if len(frame) != FRAME_LEN or frame[0] != MARKER:
        raise ExtensionError('not an extension command frame')
    if not crc_ok(frame):
        raise ExtensionError('CRC mismatch')
    return CommandFrame(frame[1], frame[2], bytes(frame[3:8]))


def decode_report(frame: bytes | bytearray) -> ReportFrame:
    """Decode a robot -> host frame; ExtensionError if it is not a report."""
    if len(frame) != FRAME_LEN or frame[0] != 0xFF or frame[1] != MARKER:
        raise ExtensionError('not an extension report frame')
    if not crc_ok(frame):
        raise ExtensionError('CRC mismatch')
    return ReportFrame(frame[2], frame[3], bytes(frame[4:8]))


def sequence_gap(previous: int | None, seq: int) -> int:
    """Frames missed between two received sequence numbers (mod 256)."""
    return 0 if previous is None else (seq - previous - 1) % 256


# ---- gait values <-> parameter frames ------------------------------------------------------

IDENTITY_LEG_MAP = (1, 2, 3, 4, 5, 6)
#: The firmware numbers legs clockwise from +x, the thesis/URDF counter-clockwise: the same
#: physical leg is URDF leg k and firmware leg ((1 - k) mod 6) + 1. Unverified on hardware.
MIRRORED_LEG_MAP = (1, 6, 5, 4, 3, 2)


def validate_leg_map(leg_map) -> tuple[int, ...]:
    """Return a permutation of 1..6: entry k-1 is the robot's number for URDF leg k."""
    try:
        mapping = tuple(int(v) for v in leg_map)
    except (TypeError, ValueError):
        raise ExtensionError(f'leg map must be six leg numbers, got {leg_map!r}') from None
    if sorted(mapping) != [1, 2, 3, 4, 5, 6]:
        raise ExtensionError(f'leg map must be a permutation of 1..6, got {list(mapping)}')
    return mapping


def urdf_legs_of_slots(leg_map) -> np.ndarray:
    """Return, for each robot slot 1..6, the index (0-based) of the URDF leg in it."""
    mapping = validate_leg_map(leg_map)
    return np.argsort(np.asarray(mapping) - 1)


def gait_in_slots(gait, leg_map):
    """Return a GaitParameters with each URDF leg's values moved to the robot's slot for it."""
    order = urdf_legs_of_slots(leg_map)
    return gait.replace(**{name: getattr(gait, name)[order] for name in LEG_FIELDS})


def gait_in_urdf_order(gait, leg_map):
    """Return the URDF-ordered GaitParameters of a gait held in the robot's slots."""
    mapping = np.asarray(validate_leg_map(leg_map)) - 1
    return gait.replace(**{name: getattr(gait, name)[mapping] for name in LEG_FIELDS})


def joints_in_slots(joints: np.ndarray, leg_map) -> np.ndarray:
    """Return joint values (..., 18; URDF legs, each coxa, femur, tibia) in the robot's slots."""
    legs = np.asarray(joints).reshape(*np.shape(joints)[:-1], 6, 3)
    return legs[..., urdf_legs_of_slots(leg_map), :].reshape(np.shape(joints))


def joints_in_urdf_order(joints: np.ndarray, leg_map) -> np.ndarray:
    """Return joint values held in the robot's slots (..., 18) in URDF leg order."""
    mapping = np.asarray(validate_leg_map(leg_map)) - 1
    legs = np.asarray(joints).reshape(*np.shape(joints)[:-1], 6, 3)
    return legs[..., mapping, :].reshape(np.shape(joints))


def gait_values(gait, leg_map=IDENTITY_LEG_MAP) -> list[float]:
    """
    Return the N_PARAMS numbers of a hexapod_gait.GaitParameters in PARAM_NAMES order.

    Each leg's values go to the robot's slot for it (``leg_map``, see validate_leg_map).
    """
    gait = gait_in_slots(gait, leg_map)
    values = [gait.body_velocity, gait.body_height, gait.period, gait.crab_angle]
    for field in LEG_FIELDS:
        values.extend(float(v) for v in getattr(gait, field))
    values.append(float(gait.archive_index))
    values.append(float(gait.turn_rate))
    return [_float32_inside(name, v) for name, v in zip(PARAM_NAMES, values)]


def _float32_inside(name: str, value: float) -> float:
    """
    Return ``value``, or if its float32 falls outside the parameter's range, the float32 inside.

    A bound such as pi has no float32: the nearest float32 lies just outside the range and the
    robot would refuse it, so such a value moves one float32 step inwards.
    """
    lo, hi = RANGES.get(name.split('[')[0], (-math.inf, math.inf))
    v = np.float32(value)
    if float(v) > hi:  # compared in float64 (NumPy would compare in float32)
        return float(np.nextafter(v, np.float32(-np.inf)))
    if float(v) < lo:
        return float(np.nextafter(v, np.float32(np.inf)))
    return value  # sent as float32 anyway


def values_crc(values: Sequence[float]) -> int:
    """CRC-16 over the float32 LE encodings of the values, index order (COMMIT's check)."""
    return crc16(b''.join(struct.pack('<f', v) for v in values))


def quantise(values: Sequence[float]) -> list[float]:
    """Return the values as the robot stores them (float32)."""
    return [struct.unpack('<f', struct.pack('<f', v))[0] for v in values]


def upload_frames(values: Sequence[float], gait_id: int, first_seq: int) -> list[bytes]:
    """SET_PARAM for every value, then COMMIT; sequence numbers first_seq, first_seq + 1, ..."""
    if len(values) != N_PARAMS:
        raise ExtensionError(f'a gait has {N_PARAMS} parameters, got {len(values)}')
    if not all(math.isfinite(v) for v in values):
        raise ExtensionError('gait parameters must be finite')
    frames = [
        encode_command(Cmd.SET_PARAM, first_seq + i, bytes([i]) + struct.pack('<f', v))
        for i, v in enumerate(values)
    ]
    commit = bytes([N_PARAMS]) + struct.pack('>HH', values_crc(quantise(values)), gait_id & 0xFFFF)
    frames.append(encode_command(Cmd.COMMIT, first_seq + N_PARAMS, commit))
    return frames


def gait_from_values(values: Sequence[float]):
    """Robot side: a validated GaitParameters from the staged values (raises its errors)."""
    v = list(values)
    legs = {
        field: v[slice(4 + 6 * k, 10 + 6 * k)]
        for k, field in enumerate(
            ('radius', 'angle_offset', 'step_height', 'duty_factor', 'phase_offset')
        )
    }
    return GaitParameters(
        body_velocity=v[0],
        body_height=v[1],
        period=v[2],
        crab_angle=v[3],
        archive_index=int(v[34]),
        turn_rate=v[35],
        **legs,
    )


#: The period of the gait a robot holds after start-up (the firmware's compiled-in tripod) [s].
FIRMWARE_GAIT_PERIOD = 1.0
#: Upper estimate of the time the firmware module (firmware/) takes to compile one row of a gait's
#: 120 Hz table on the robot's 168 MHz Cortex-M4 [s]: soft-float double precision, measured as
#: instruction counts on QEMU (docs/benchmarks.md, firmware), at 1.5 cycles per instruction,
#: rounded up.
COMMIT_SECONDS_PER_ROW = 0.002


def commit_compile_time(period: float, previous_period: float) -> float:
    """
    Return how long a robot may take to answer a COMMIT of a gait with this period [s].

    It compiles the new gait's table; if that fails at its last row, it compiles the previous
    gait's table again (the last good state), and only then acknowledges.
    """
    rows = sum(max(2, round(p * ROBOT_TABLE_RATE)) for p in (period, previous_period))
    return rows * COMMIT_SECONDS_PER_ROW


def start_payload(duration_s: float, gait_id: int, stand_first: bool = False) -> bytes:
    """START_TRIAL's payload: duration in ms and the gait id; ExtensionError if out of range."""
    ms = int(round(duration_s * 1000))
    if not 100 <= ms <= 60000:
        raise ExtensionError(f'trial duration must be 0.1..60 s, got {duration_s:g}')
    return struct.pack('>HHB', ms, gait_id & 0xFFFF, 1 if stand_first else 0)
