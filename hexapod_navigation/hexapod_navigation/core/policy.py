# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""What a navigation policy is: it chooses steps toward a goal and hears how each went."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from hexapod_gait import GaitParameters
from hexapod_navigation.core.geometry import Pose2D


@dataclass(frozen=True)
class Step:
    """The next step a policy wants: a gait, how long, and where it expects to end."""

    gait: GaitParameters
    duration: float  # s
    predicted: Pose2D  # expected pose at the end (odom)
    index: int = -1  # repertoire row, -1 for a baseline's gait
    tripod: int = -1  # the steered tripod's crab direction (0..7), -1 for another gait


class Policy(Protocol):
    """Chooses steps toward a goal, and hears how each went."""

    def next_step(
        self,
        pose: Pose2D,
        goal: tuple[float, float],
        playing: GaitParameters | None = None,
        switch_time: float = 0.0,
    ) -> Step:
        """
        Return the step to take from ``pose``.

        ``playing``: the gait the body would go on with (None: it stands); any other gait first
        costs ``switch_time`` s of moving the legs to its first pose (the body's transition),
        which the step's duration includes.
        """

    def observe(self, step: Step, start: Pose2D, end: Pose2D, completed: bool) -> float | None:
        """Learn from a step; return its prediction error [m] (None if not predicted)."""

    def avoid(self, step: Step) -> None:
        """Never take ``step``'s gait again: it tilted the body past the tip guard."""
