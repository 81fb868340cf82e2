# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A serial port that survives the device disappearing.

Reads return b"" while it is gone, reopening is retried with a capped back-off, and a closed port
holds no file descriptor.
"""

from __future__ import annotations

import select
import time

import serial


class ReconnectingPort:
    """A serial port that reopens itself after the device goes away (backing off)."""

    def __init__(self, path: str, baud: int, max_backoff: float = 0.5) -> None:
        self.path = path
        self.baud = baud
        self.max_backoff = max_backoff
        self.port: serial.Serial | None = None
        self.last_error = ''
        self.connects = 0
        self._backoff = 0.05
        self._next_try = 0.0

    @property
    def connected(self) -> bool:
        """Return True while the port is open."""
        return self.port is not None

    def ensure_open(self, now: float) -> bool:
        """Try to (re)open the port when it is due; True if it is open."""
        if self.port is not None:
            return True
        if now < self._next_try:
            return False
        try:
            self.port = serial.Serial(
                self.path, self.baud, timeout=0, write_timeout=0.5, exclusive=True
            )
            self.connects += 1
            self._backoff = 0.05
            self.last_error = ''
            return True
        except (serial.SerialException, OSError, ValueError) as exc:
            self.last_error = f'cannot open {self.path}: {exc}'
            self._next_try = now + self._backoff
            self._backoff = min(self.max_backoff, self._backoff * 2)
            return False

    def close(self, reason: str = '') -> None:
        """Close the port (a later ensure_open reopens it)."""
        if self.port is not None:
            try:
                self.port.close()
            except (serial.SerialException, OSError):
                pass
            self.port = None
            if reason:
                self.last_error = reason
            self._next_try = time.monotonic()

    def read(self, timeout: float) -> bytes:
        """Bytes available within timeout (b"" if none or the port is down)."""
        if self.port is None:
            time.sleep(timeout)
            return b''
        try:
            ready = select.select([self.port.fileno()], [], [], timeout)[0]
            if not ready:
                return b''
            data = self.port.read(self.port.in_waiting or 1)
            if not data:
                raise serial.SerialException(
                    'device reports readiness to read but returned no data'
                )
            return data
        except (serial.SerialException, OSError, TypeError, ValueError) as exc:
            self.close(f'{self.path} lost: {exc}')
            return b''

    def write(self, data: bytes) -> bool:
        """Write bytes; False (and the port closed) if the device went away."""
        if self.port is None or not data:
            return False
        try:
            self.port.write(data)
            return True
        except (serial.SerialException, OSError) as exc:
            self.close(f'{self.path} lost while writing: {exc}')
            return False
