# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The robot's current radio protocol (robot-facts.md), encoded and decoded exactly.

PC -> robot: every message is exactly 10 bytes (the robot reads a fixed 10-byte buffer).
  movement   [0x01, dir, twist, 0x02, speed, 0x03, height, 0x04, function, sum(b0..b8) & 0xFF]
             The facts give the marker layout "01 dir 02 speed 03 height 04 function" and the
             field offsets twist = b2, speed = b4, height = b6; read together, the markers 02,
             03, 04 sit at b3, b5, b7 and the function code at b8.
  ping       [0x37, 0 x 9]                          (keep-alive; bytes 1..9 ignored)
  motor      [0xFF, 0xFA, on, 0 x 7]
  pid on/off [0xFF, 0xFB, on, axis, 0 x 6]          axis 1 pitch, 2 roll, 3 both
  pid gain   [0xFF, 0xDE, axis, gain, f32 LE, 0, 0] gain 1 Kp, 2 Ki, 3 Kd
  imu period [0xFF, 0xDD, f32 LE, 0 x 4]            telemetry period [s]
  charging   [0xFF, 0xF8, 0x37, 1/0, 0 x 6]         start/stop charging
Robot -> PC (no length byte, no checksum unless stated):
  telemetry  FF FE + 6 x f32 LE: sample counter, pitch, roll, yaw [rad], slope pitch, slope roll
  ping reply FF FA
  error      FF FD loc code
  text       FF FC len text[len]
  charger    FF F9 status f32-voltage(LE) 0 0 sum(b0..b8)   (10 bytes; layout of b2..b8 is ours)
  move ack   FF <checksum of the acknowledged movement frame>
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum
import math
import struct

FRAME_LEN = 10
PING_BYTE = 0x37


class Direction(IntEnum):
    """Movement direction codes and the crab angle each one commands [rad]."""

    STOP = 0
    FORWARD = 1  # 0
    BACKWARD = 2  # pi
    RIGHT = 3  # -pi/2
    LEFT = 4  # +pi/2
    FORWARD_LEFT = 5  # pi/4
    BACKWARD_LEFT = 6  # 3pi/4
    FORWARD_RIGHT = 7  # -pi/4
    BACKWARD_RIGHT = 8  # -3pi/4


DIRECTION_ANGLE = {
    Direction.FORWARD: 0.0,
    Direction.BACKWARD: math.pi,
    Direction.RIGHT: -math.pi / 2,
    Direction.LEFT: math.pi / 2,
    Direction.FORWARD_LEFT: math.pi / 4,
    Direction.BACKWARD_LEFT: 3 * math.pi / 4,
    Direction.FORWARD_RIGHT: -math.pi / 4,
    Direction.BACKWARD_RIGHT: -3 * math.pi / 4,
}


class Function(IntEnum):
    """Movement frame function codes (robot-facts.md)."""

    WALK = 0
    STAND = 2
    TURN_LEFT = 3  # -0.3 rad
    TURN_RIGHT = 4  # +0.3 rad
    TOGGLE_LIFT = 5
    RESET = 55  # full microcontroller reset: restarts the 5 s walk


class ProtocolError(ValueError):
    """A value cannot be encoded, or bytes do not form a valid frame; says which and why."""


def checksum8(data: bytes | bytearray) -> int:
    """Return the movement frame's checksum: sum of the bytes mod 256."""
    return sum(data) & 0xFF


@dataclass(frozen=True)
class Movement:
    """A legacy movement command (direction code, twist, speed, height, function)."""

    direction: int = Direction.FORWARD
    twist: float = 0.0  # rad, b2 / 100 - 1
    speed: float = 0.0  # b4 / 100
    height_mm: float = 140.0  # 280 * b6 / 100, accepted by the robot in 50..240 mm
    function: int = Function.WALK


def encode_movement(m: Movement) -> bytes:
    """Return the 10-byte movement frame; ValueError for a value the frame cannot carry."""
    if not 0 <= int(m.direction) <= 8:
        raise ProtocolError(f'direction code must be 0..8, got {m.direction}')
    twist = round((m.twist + 1.0) * 100)
    speed = round(m.speed * 100)
    height = round(m.height_mm * 100 / 280)
    for name, value in (('twist', twist), ('speed', speed), ('height', height)):
        if not 0 <= value <= 255:
            raise ProtocolError(f'{name} does not fit one byte ({value})')
    if not 50 <= 280 * height / 100 <= 240:
        raise ProtocolError(f"height {m.height_mm:g} mm outside the robot's 50..240 mm")
    if not 0 <= int(m.function) <= 255:
        raise ProtocolError(f'function code must fit one byte, got {m.function}')
    body = bytes([0x01, int(m.direction), twist, 0x02, speed, 0x03, height, 0x04, int(m.function)])
    return body + bytes([checksum8(body)])


def decode_movement(frame: bytes) -> Movement:
    """Robot side: decode and validate a movement frame (checksum, markers, ranges)."""
    if len(frame) != FRAME_LEN or frame[0] != 0x01:
        raise ProtocolError('not a movement frame')
    if checksum8(frame[:9]) != frame[9]:
        raise ProtocolError('movement checksum mismatch')
    if (frame[3], frame[5], frame[7]) != (0x02, 0x03, 0x04):
        raise ProtocolError('movement frame markers 02/03/04 missing')
    if frame[1] > 8:
        raise ProtocolError(f'unknown direction code {frame[1]}')
    height = 280 * frame[6] / 100
    if not 50 <= height <= 240:
        raise ProtocolError(f'height {height:g} mm outside 50..240 mm')
    return Movement(frame[1], frame[2] / 100 - 1.0, frame[4] / 100, height, frame[8])


def _pad(body: bytes) -> bytes:
    return body + bytes(FRAME_LEN - len(body))


def encode_ping() -> bytes:
    """Return the 10-byte keep-alive frame."""
    return _pad(bytes([PING_BYTE]))


def encode_motor_power(on: bool) -> bytes:
    """Return the 10-byte motor power frame (FF FA on)."""
    return _pad(bytes([0xFF, 0xFA, 1 if on else 0]))


def encode_pid_enable(on: bool, axis: int) -> bytes:
    """Return the 10-byte levelling PID on/off frame."""
    if axis not in (1, 2, 3):
        raise ProtocolError(f'PID axis must be 1 (pitch), 2 (roll) or 3 (both), got {axis}')
    return _pad(bytes([0xFF, 0xFB, 1 if on else 0, axis]))


def encode_pid_gain(axis: int, gain: int, value: float) -> bytes:
    """Return the 10-byte PID gain frame."""
    if axis not in (1, 2, 3) or gain not in (1, 2, 3):
        raise ProtocolError(f'PID axis and gain must be 1..3, got {axis}, {gain}')
    if not math.isfinite(value):
        raise ProtocolError('PID gain must be finite')
    return _pad(bytes([0xFF, 0xDE, axis, gain]) + struct.pack('<f', value))


def encode_imu_period(seconds: float) -> bytes:
    """Return the 10-byte telemetry period frame (FF DD, float32 seconds)."""
    if not (math.isfinite(seconds) and 0.05 <= seconds <= 60.0):
        raise ProtocolError(f'telemetry period must be 0.05..60 s, got {seconds}')
    return _pad(bytes([0xFF, 0xDD]) + struct.pack('<f', seconds))


def encode_charging(start: bool) -> bytes:
    """Return the 10-byte charging base start/stop frame."""
    return _pad(bytes([0xFF, 0xF8, 0x37, 1 if start else 0]))


# ---- robot -> PC ---------------------------------------------------------------------------


@dataclass(frozen=True)
class Telemetry:
    """Robot attitude telemetry (FF FE): sample counter, pitch, roll, yaw, slope [rad]."""

    counter: float
    pitch: float
    roll: float
    yaw: float
    slope_pitch: float
    slope_roll: float


@dataclass(frozen=True)
class PingReply:
    """The robot's ping reply (FF FA)."""

    pass


@dataclass(frozen=True)
class ErrorReport:
    """A robot error report (FF FD loc code)."""

    location: (
        int  # 1 servo bus, 2 radio, 3 IMU, 11 servo ping failed (code = servo id); else HAL bits
    )
    code: int

    def describe(self) -> str:
        """Return the error in words (location and code)."""
        names = {1: 'servo bus', 2: 'radio', 3: 'IMU', 11: 'servo ping failed'}
        if self.location == 11:
            return f'servo {self.code} did not answer a ping'
        bits = [
            name
            for bit, name in (
                (1, 'parity'),
                (2, 'noise'),
                (4, 'framing'),
                (8, 'overrun'),
                (0x10, 'DMA'),
            )
            if self.code & bit
        ]
        return (
            f'{names.get(self.location, f"location {self.location}")} error:'
            f' {", ".join(bits) or hex(self.code)}'
        )


@dataclass(frozen=True)
class Text:
    """An ASCII message from the robot (FF FC len text)."""

    text: str


@dataclass(frozen=True)
class ChargerStatus:
    """Charger status and battery voltage (FF F9)."""

    status: int
    voltage: float


@dataclass(frozen=True)
class MovementAck:
    """The robot's acknowledgement of a movement frame (FF <checksum>)."""

    checksum: int


TELEMETRY_LEN = 26


def encode_telemetry(t: Telemetry) -> bytes:
    """Robot side: a 26-byte telemetry frame."""
    return bytes([0xFF, 0xFE]) + struct.pack(
        '<6f', t.counter, t.pitch, t.roll, t.yaw, t.slope_pitch, t.slope_roll
    )


def encode_error(location: int, code: int) -> bytes:
    """Robot side: an error report frame."""
    return bytes([0xFF, 0xFD, location & 0xFF, code & 0xFF])


def encode_text(text: str) -> bytes:
    """Robot side: a text frame (at most MAX_TEXT bytes)."""
    data = text.encode('ascii', errors='replace')[:255]
    return bytes([0xFF, 0xFC, len(data)]) + data


def encode_charger(status: int, voltage: float) -> bytes:
    """Robot side: a charger status frame."""
    body = bytes([0xFF, 0xF9, status & 0xFF]) + struct.pack('<f', voltage) + bytes(2)
    return body + bytes([checksum8(body)])


def encode_ack(checksum: int) -> bytes:
    """Robot side: the acknowledgement of a movement frame with this checksum."""
    return bytes([0xFF, checksum & 0xFF])
