# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""CRC-16 (hexapod_bridge.protocol.crc)."""

from __future__ import annotations

from hexapod_bridge.protocol.crc import crc16


def test_crc16_check_value():
    assert crc16(b'123456789') == 0x29B1
