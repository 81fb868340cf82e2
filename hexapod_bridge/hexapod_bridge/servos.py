# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The robot's Dynamixel servo ids and the legs they belong to (robot-facts.md).

Leg i (1..6, the robot's numbering) has coxa, femur and tibia servos 3i-1, 3i and 3i+1, so the
ids run 2..19. The robot reports a servo that does not answer its ping as ``FF FD 0B <id>``.
"""

from __future__ import annotations

from dataclasses import dataclass

JOINTS = ('coxa', 'femur', 'tibia')
SERVO_IDS = tuple(range(2, 20))
#: Error-frame location of a failed servo ping (FF FD 0B <servo id>).
SERVO_PING_FAILED = 0x0B


def servo_id(robot_leg: int, joint: int) -> int:
    """Return the servo id of a robot leg (1..6) and joint (0 coxa, 1 femur, 2 tibia)."""
    if not (1 <= robot_leg <= 6 and 0 <= joint <= 2):
        raise ValueError(f'no servo for leg {robot_leg}, joint {joint}')
    return 3 * robot_leg - 1 + joint


@dataclass(frozen=True)
class ServoPlace:
    """Where a servo sits: the robot's leg number (1..6) and the joint."""

    robot_leg: int
    joint: str


def servo_place(servo: int) -> ServoPlace | None:
    """Return the leg and joint of a servo id, or None for an id the robot does not have."""
    if servo not in SERVO_IDS:
        return None
    return ServoPlace((servo - 2) // 3 + 1, JOINTS[(servo - 2) % 3])
