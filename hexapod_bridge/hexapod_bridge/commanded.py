# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The robot's commanded joint angles, for ``joint_states`` on the robot (the legs in 3D).

The radio carries no servo positions, so bridge_node publishes what the firmware plays: the
uploaded gait's joint table (the one gait_node builds for the simulator) from the moment a trial
starts, and the table's first row while the robot stands. They are commands, not measurements.
"""

from __future__ import annotations

from hexapod_gait import GaitParameters
from hexapod_gait.trajectory import build_joint_table, JointTable, ReachabilityError
import numpy as np


class CommandedJoints:
    """The uploaded gait's joint table, and the angles it commands at a time into a walk."""

    def __init__(self) -> None:
        self.table: JointTable | None = None

    def set_gait(self, gait: GaitParameters) -> None:
        """Take the gait the robot now walks (one the robot accepted is reachable)."""
        try:
            self.table = build_joint_table(gait)
        except (ReachabilityError, ValueError):  # the robot checks its own; nothing to show
            self.table = None

    def positions(self, walked: float | None) -> np.ndarray | None:
        """
        Return the 18 commanded angles [rad], URDF order, ``walked`` s into a walk.

        ``walked`` None: the robot stands (the table's first row). None without a gait.
        """
        if self.table is None:
            return None
        if walked is None:
            return self.table.positions[0]
        row = int(walked * self.table.rate) % len(self.table)
        return self.table.positions[row]
