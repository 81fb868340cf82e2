# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Stream parsers that resynchronise after garbage and count what they drop.

HostParser   robot -> PC bytes (legacy frames of variable length + extension reports)
RobotReceiver PC -> robot bytes (10-byte frames), the receive path specified for firmware v2:
             aligned while frames validate, sliding one byte at a time when they do not
Both keep a bounded buffer and never raise on input.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import math
import struct
from typing import Union

from hexapod_bridge.protocol import extension as ext
from hexapod_bridge.protocol import legacy
from hexapod_bridge.servos import SERVO_PING_FAILED

MAX_TEXT = 64  # longest text frame accepted (robot messages are short, e.g. "LOW BATTERY")
CHUNK = 256  # input is processed in slices of at most this many bytes
TYPE_LENGTHS = {0xFE: legacy.TELEMETRY_LEN, 0xFA: 2, 0xFD: 4, 0xF9: 10, ext.MARKER: ext.FRAME_LEN}
#: Movement-ack checksums a parser could not tell from a frame header ("FF FE" ...).
AMBIGUOUS_ACKS = frozenset(TYPE_LENGTHS) | {0xFC, 0xFF}

HostFrame = Union[
    legacy.Telemetry,
    legacy.PingReply,
    legacy.ErrorReport,
    legacy.Text,
    legacy.ChargerStatus,
    legacy.MovementAck,
    ext.ReportFrame,
]


@dataclass
class ParserStats:
    """Counters of a stream parser: frames, checksum errors, resyncs, dropped bytes."""

    frames_ok: int = 0
    checksum_errors: int = 0  # frames with a checksum/CRC that did not match
    implausible: int = 0  # frames without a checksum whose values were impossible
    resyncs: int = 0  # times bytes were skipped to find the next frame
    bytes_dropped: int = 0
    max_buffer: int = 0  # largest buffer length seen (bounded by design)
    by_type: dict = field(default_factory=dict)


class ResyncBuffer:
    """
    What every stream parser shares.

    A buffer fed in slices of at most CHUNK bytes (so it stays bounded), statistics, and counting a
    run of skipped bytes as one resync. Subclasses implement ``_drain`` (take frames off the front
    of the buffer) and never raise on input.
    """

    def __init__(self) -> None:
        self.buffer = bytearray()
        self.stats = ParserStats()
        self._skipping = False

    def feed(self, data: bytes) -> list:
        """Add received bytes; return the frames they complete."""
        out: list = []
        for start in range(0, len(data), CHUNK):
            end = start + CHUNK
            self.buffer += data[start:end]
            self.stats.max_buffer = max(self.stats.max_buffer, len(self.buffer))
            self._drain(out)
        return out

    def _drain(self, out: list) -> None:
        raise NotImplementedError

    def _drop(self, n: int) -> None:
        """Skip n bytes while looking for the next frame."""
        if n <= 0:
            return
        if not self._skipping:
            self.stats.resyncs += 1
            self._skipping = True
        self.stats.bytes_dropped += n
        del self.buffer[:n]

    def _take(self, n: int) -> None:
        """Note that a valid frame of n bytes was taken off the front: in sync again."""
        del self.buffer[:n]
        self._skipping = False
        self.stats.frames_ok += 1


def _telemetry_plausible(t: legacy.Telemetry) -> bool:
    values = (t.counter, t.pitch, t.roll, t.yaw, t.slope_pitch, t.slope_roll)
    if not all(math.isfinite(v) for v in values):
        return False
    return (
        0 <= t.counter < 2**24
        and t.counter == int(t.counter)
        and abs(t.pitch) <= math.pi
        and abs(t.roll) <= math.pi
        and abs(t.yaw) <= 2 * math.pi
        and abs(t.slope_pitch) <= math.pi / 2
        and abs(t.slope_roll) <= math.pi / 2
    )


def _error_plausible(loc: int, code: int) -> bool:
    # a failed servo ping names any Dynamixel id (0..253): the bridge, not the parser, refuses
    # ids the robot does not have, so such a report is seen and logged
    return (loc in (1, 2, 3) and 1 <= code <= 0x1F) or (loc == SERVO_PING_FAILED and code <= 253)


class HostParser(ResyncBuffer):
    """Robot -> PC byte stream to frames."""

    def _drain(self, out: list[HostFrame]) -> None:
        buf = self.buffer
        while buf:
            self._drop(buf.find(0xFF) if 0xFF in buf else len(buf))
            if len(buf) < 2:
                return
            kind = buf[1]
            if kind == 0xFF:
                # "FF FF" is never read as an ack: the second FF may start a real frame (the
                # link never sends a movement frame whose checksum would be ambiguous)
                self._drop(1)
                continue
            if kind == 0xFC:
                if len(buf) < 3:
                    return
                length = 3 + buf[2]
                if buf[2] == 0 or buf[2] > MAX_TEXT:
                    self.stats.implausible += 1
                    self._drop(1)
                    continue
            else:
                length = TYPE_LENGTHS.get(kind, 2)
            if len(buf) < length:
                return
            frame = self._decode(bytes(buf[:length]))
            if frame is None:
                self._drop(1)
                continue
            self._take(length)
            name = type(frame).__name__
            self.stats.by_type[name] = self.stats.by_type.get(name, 0) + 1
            out.append(frame)

    def _decode(self, raw: bytes) -> HostFrame | None:
        kind = raw[1]
        s = self.stats
        if kind == 0xFE:
            t = legacy.Telemetry(*struct.unpack('<6f', raw[2:26]))
            if _telemetry_plausible(t):
                return t
            s.implausible += 1
            return None
        if kind == 0xFA:
            return legacy.PingReply()
        if kind == 0xFD:
            if _error_plausible(raw[2], raw[3]):
                return legacy.ErrorReport(raw[2], raw[3])
            s.implausible += 1
            return None
        if kind == 0xFC:
            text = raw[3:]
            if all(0x20 <= c <= 0x7E for c in text):
                return legacy.Text(text.decode('ascii'))
            s.implausible += 1
            return None
        if kind == 0xF9:
            if legacy.checksum8(raw[:9]) != raw[9]:
                s.checksum_errors += 1
                return None
            voltage = struct.unpack('<f', raw[3:7])[0]
            if not (math.isfinite(voltage) and 0.0 <= voltage <= 60.0):
                s.implausible += 1
                return None
            return legacy.ChargerStatus(raw[2], voltage)
        if kind == ext.MARKER:
            if not ext.crc_ok(raw):
                s.checksum_errors += 1
                return None
            return ext.decode_report(raw)
        return legacy.MovementAck(kind)


# ---- robot side --------------------------------------------------------------------------


@dataclass(frozen=True)
class PingFrame:
    """A keep-alive frame as the robot receives it."""

    pass


@dataclass(frozen=True)
class LegacyCommand:
    """A legacy FF-command: code (b1) and the raw 10 bytes."""

    code: int
    raw: bytes


RobotFrame = Union[legacy.Movement, PingFrame, LegacyCommand, ext.CommandFrame]
_FF_CODES = {0xFA, 0xFB, 0xDE, 0xDD, 0xF8}
#: First padding byte of each FF command (everything from there to byte 9 is zero).
_FF_PADDING = {0xFA: 3, 0xFB: 4, 0xDE: 8, 0xDD: 6, 0xF8: 4}


class RobotReceiver(ResyncBuffer):
    """PC -> robot byte stream to frames (firmware v2 receive path)."""

    def __init__(self) -> None:
        super().__init__()
        self.last_checksum: int | None = None  # of the last movement frame (for its ack)

    def _drain(self, out: list) -> None:
        while len(self.buffer) >= legacy.FRAME_LEN:
            frame = self._decode(bytes(self.buffer[: legacy.FRAME_LEN]))
            if frame is None:
                self._drop(1)
                continue
            self._take(legacy.FRAME_LEN)
            out.append(frame)

    def _decode(self, raw: bytes) -> RobotFrame | None:
        b0 = raw[0]
        if b0 == ext.MARKER:
            if ext.crc_ok(raw):
                return ext.decode_command(raw)
            self.stats.checksum_errors += 1
            return None
        if b0 == 0x01:
            if legacy.checksum8(raw[:9]) != raw[9]:
                self.stats.checksum_errors += 1
                return None
            try:
                movement = legacy.decode_movement(raw)
            except legacy.ProtocolError:
                self.stats.implausible += 1
                return None
            self.last_checksum = raw[9]
            return movement
        # Legacy frames without a checksum. Aligned, they are taken as today's firmware takes
        # them. While resynchronising, garbage could look like them, so only the exact form the
        # bridge sends is accepted: a ping with nine zero bytes, an FF command with zero padding.
        # (Without this a receiver that lost sync while only pings flow would never recover.)
        if b0 == legacy.PING_BYTE:
            return PingFrame() if not self._skipping or not any(raw[1:]) else None
        if b0 == 0xFF and raw[1] in _FF_CODES:
            if self._skipping and any(raw[slice(_FF_PADDING[raw[1]], None)]):
                return None
            return LegacyCommand(raw[1], raw)
        return None
