# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The servo targets the robot's firmware writes (firmware.cpp ``write_targets``), with the fold.

The model of :mod:`hexapod_bridge.emulator.firmware` drives its simulator at the simulator's
rate; this tracks what the C++ module writes to the servo bus at 120 Hz, so the differential tests
compare the two: the walk's table row of the elapsed time, the transition to a new gait's first
pose while standing, and the fold policy (:mod:`hexapod_sim.damage`): the live joints of a leg
with a dead servo hold the failure pose.
"""

from __future__ import annotations

from hexapod_bridge.servos import SERVO_IDS
from hexapod_gait import ROBOT_RATE
from hexapod_gait.trajectory import POSE_TRANSITION_S
from hexapod_sim.damage import FAILURE_POSE
import numpy as np

N_JOINTS = 18
_RATE_HZ = int(ROBOT_RATE)
_TRANSITION_MS = round(POSE_TRANSITION_S * 1000)


def leg_servos(leg: int) -> set[int]:
    """Return the servo ids of leg ``leg`` (0..5): coxa, femur, tibia."""
    return {SERVO_IDS[0] + 3 * leg + k for k in range(3)}


class ServoTargets:
    """The last targets written to the 18 servos, and how many writes there were."""

    def __init__(self, first_pose: np.ndarray) -> None:
        self.position = np.asarray(first_pose, dtype=np.float32).copy()
        self.writes = 0
        self.dead: frozenset[int] = frozenset()
        self._last_row = -1
        self._pending = False
        self._moving = False
        self._start_ms = 0
        self._step = 0
        self._from = self.position.copy()
        self._write()

    def _write(self) -> None:
        for leg in range(6):
            if self.dead & leg_servos(leg):
                joints = slice(3 * leg, 3 * leg + 3)
                self.position[joints] = np.float32(FAILURE_POSE)
        self.writes += 1

    def gait_loaded(self, walking: bool) -> None:
        """Take a new gait: standing, the legs move to its first pose."""
        if not walking:
            self._pending = True

    def walk_started(self) -> None:
        """Begin a walk: its rows are written from its start."""
        self._last_row = -1
        self._moving = self._pending = False

    def health_checked(self, dead: frozenset[int], first_pose: np.ndarray) -> None:
        """Take the health check's ``dead`` servos: fold their legs, unfold repaired ones, now."""
        if dead == self.dead:
            return
        for leg in range(6):
            if self.dead & leg_servos(leg) and not dead & leg_servos(leg):
                joints = slice(3 * leg, 3 * leg + 3)
                self.position[joints] = first_pose[joints]
        self.dead = dead
        self._write()

    def update(self, now_ms: int, walking: bool, walk_start_ms: int, table: np.ndarray) -> None:
        """Write what the firmware writes at ``now_ms`` (``table``: the 120 Hz positions)."""
        if walking:
            row = (now_ms - walk_start_ms) * _RATE_HZ // 1000
            if row == self._last_row:
                return
            self._last_row = row
            self.position = table[row % len(table)].astype(np.float32)
            self._write()
            return
        if self._pending:
            self._pending, self._moving = False, True
            self._start_ms, self._step = now_ms, 0
            self._from = self.position.copy()
        if not self._moving:
            return
        steps = _TRANSITION_MS * _RATE_HZ // 1000
        step = min((now_ms - self._start_ms) * _RATE_HZ // 1000 + 1, steps)
        if step == self._step:
            return
        self._step = step
        fraction = np.float32(step) / np.float32(steps)
        self.position = self._from + fraction * (table[0].astype(np.float32) - self._from)
        self._write()
        if step == steps:
            self._moving = False
