# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Planar poses in the odom frame (ROS-free)."""

from __future__ import annotations

from dataclasses import dataclass
import math


def wrap_angle(a: float) -> float:
    """Return ``a`` [rad] wrapped into (-pi, pi]."""
    return math.pi - (math.pi - a) % (2.0 * math.pi)


@dataclass(frozen=True)
class Pose2D:
    """A planar pose in the odom frame: position [m] and heading [rad]."""

    x: float
    y: float
    yaw: float

    def distance_to(self, x: float, y: float) -> float:
        """Return the distance from this pose's position to (x, y) [m]."""
        return math.hypot(x - self.x, y - self.y)

    def relative(self, later: 'Pose2D') -> tuple[float, float, float]:
        """Return ``later`` in this pose's frame: (dx, dy) [m] and the heading change [rad]."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        dx, dy = later.x - self.x, later.y - self.y
        return c * dx + s * dy, -s * dx + c * dy, wrap_angle(later.yaw - self.yaw)

    def moved(self, dx: float, dy: float, dyaw: float) -> 'Pose2D':
        """Return the pose reached by a step (dx, dy, dyaw) given in this pose's frame."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return Pose2D(self.x + c * dx - s * dy, self.y + s * dx + c * dy, self.yaw + dyaw)
