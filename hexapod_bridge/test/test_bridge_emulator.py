# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The robot emulator's firmware (hexapod_bridge.emulator.firmware): failsafe."""

from __future__ import annotations

from hexapod_bridge.emulator.firmware import RobotFirmware


def test_failsafe_trips_without_pings():
    fw = RobotFirmware(failsafe_windows=11)
    fw.start_walk(0.0, 60.0)
    t = 0.0
    while t < 40.0 and fw.walking:
        t += 0.05
        fw.advance(t)
    assert not fw.walking and fw.stats.failsafe_trips == 1
    assert 11 * 2.5 - 0.1 <= t <= 12 * 2.5 + 0.1
