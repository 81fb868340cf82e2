# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Xsens Xbus messages (hexapod_bridge.protocol.xbus)."""

from __future__ import annotations

from hexapod_bridge.protocol import xbus
import pytest


def test_xbus_commands_and_mtdata():
    for command in (xbus.GO_TO_CONFIG, xbus.GO_TO_MEASUREMENT, xbus.HEADING_RESET, xbus.REQ_DATA):
        assert sum(command[1:]) & 0xFF == 0
    assert xbus.encode(0xFF, 0x30) == xbus.GO_TO_CONFIG
    m = xbus.MTData(
        (0.1, -0.2, 9.8), (0.01, 0.02, -0.03), (1.0, 0.0, 0.5), (1.5, -2.0, 170.0), 65535
    )
    raw = xbus.encode_mtdata(m)
    assert len(raw) == 55 and raw[:4] == bytes([0xFA, 0x01, 0x32, 50])
    parser = xbus.XbusParser()
    out = parser.feed(b'\xfa\x00garbage\xfa' + raw + raw[:20])
    assert len(out) == 1 and out[0].counter == 65535 and out[0].euler[2] == pytest.approx(170.0)
    assert out[0].acc[2] == pytest.approx(9.8, abs=1e-6)
    # the message cut after 20 bytes is whole once the rest comes
    assert parser.feed(bytes(raw[20:])) == [out[0]]
    corrupted = bytearray(raw)
    corrupted[10] ^= 1
    fresh = xbus.XbusParser()
    assert fresh.feed(bytes(corrupted) + raw)[0] == out[0] and fresh.stats.checksum_errors == 1
