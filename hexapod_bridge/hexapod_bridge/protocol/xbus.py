# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Xsens Xbus framing for an MTi wired to the PC's own serial port (robot-facts.md).

Message: FA (preamble), bus id, message id, length, data[length], checksum, where the sum of
every byte after the preamble is 0 mod 256. MTData (0x32) in the configured output mode
(0x0006, settings 0x00000005) carries 50 bytes, all big-endian: acc x/y/z [m/s^2], gyr x/y/z
[rad/s], mag x/y/z [a.u.], Euler roll/pitch/yaw [deg], uint16 sample counter.
"""

from __future__ import annotations

from dataclasses import dataclass
import math
import struct

from hexapod_bridge.protocol.stream import ResyncBuffer

PREAMBLE = 0xFA
MID_MTDATA = 0x32
MTDATA_LEN = 50
MAX_DATA = 254  # extended-length messages (length byte 0xFF) are not used by the MTi-28
#: In measurement mode the MTi sends MTData and short replies; a header announcing more than
#: this (other than MTData's 50) is garbage, rejected at once instead of waiting for its bytes.
MAX_OTHER_DATA = 64

GO_TO_CONFIG = bytes([0xFA, 0xFF, 0x30, 0x00, 0xD1])
GO_TO_MEASUREMENT = bytes([0xFA, 0xFF, 0x10, 0x00, 0xF1])
HEADING_RESET = bytes([0xFA, 0xFF, 0xA4, 0x02, 0x00, 0x01, 0x5A])
REQ_DATA = bytes([0xFA, 0x01, 0x34, 0x00, 0xCB])


def encode(bus_id: int, message_id: int, data: bytes = b'') -> bytes:
    """Return an Xbus message (preamble, bus id, message id, length, data, checksum)."""
    if len(data) > MAX_DATA:
        raise ValueError(f'Xbus data is at most {MAX_DATA} bytes')
    body = bytes([bus_id & 0xFF, message_id & 0xFF, len(data)]) + data
    return bytes([PREAMBLE]) + body + bytes([(-sum(body)) & 0xFF])


@dataclass(frozen=True)
class MTData:
    """One Xsens MTData sample: acceleration, turn rate, magnetic field, Euler angles, counter."""

    acc: tuple[float, float, float]  # m/s^2, sensor frame (specific force)
    gyr: tuple[float, float, float]  # rad/s
    mag: tuple[float, float, float]  # arbitrary units
    euler: tuple[float, float, float]  # roll, pitch, yaw [deg]
    counter: int  # uint16 sample counter


def encode_mtdata(m: MTData, bus_id: int = 0x01) -> bytes:
    """Return the 55-byte MTData message the firmware expects."""
    data = struct.pack('>12fH', *m.acc, *m.gyr, *m.mag, *m.euler, m.counter & 0xFFFF)
    return encode(bus_id, MID_MTDATA, data)


def _plausible(m: MTData) -> bool:
    values = m.acc + m.gyr + m.mag + m.euler
    if not all(math.isfinite(v) for v in values):
        return False
    return (
        all(abs(a) <= 200.0 for a in m.acc)
        and all(abs(w) <= 35.0 for w in m.gyr)
        and abs(m.euler[0]) <= 180.0
        and abs(m.euler[1]) <= 90.0
        and abs(m.euler[2]) <= 180.0
    )


class XbusParser(ResyncBuffer):
    """Bytes from the IMU to MTData (and other messages as (mid, data)); never raises."""

    def _drain(self, out: list) -> None:
        buf = self.buffer
        while buf:
            self._drop(buf.find(PREAMBLE) if PREAMBLE in buf else len(buf))
            if len(buf) < 4:
                return
            length = buf[3]
            if length > MAX_OTHER_DATA or (buf[2] == MID_MTDATA and length != MTDATA_LEN):
                self.stats.implausible += 1
                self._drop(1)
                continue
            total = 5 + length
            if len(buf) < total:
                return
            if sum(buf[1:total]) & 0xFF:
                self.stats.checksum_errors += 1
                self._drop(1)
                continue
            mid, data = buf[2], bytes(buf[slice(4, 4 + length)])
            if mid == MID_MTDATA:  # length checked above
                v = struct.unpack('>12fH', data)
                msg = MTData(tuple(v[0:3]), tuple(v[3:6]), tuple(v[6:9]), tuple(v[9:12]), v[12])
                if not _plausible(msg):
                    self.stats.implausible += 1
                    self._drop(1)
                    continue
                out.append(msg)
            else:
                out.append((mid, data))
            self._take(total)
