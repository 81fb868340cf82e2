# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The steered tripod: the firmware's control tripod in its eight crab directions.

What the robot can always walk, damaged or not: the navigation baseline
(:class:`SteeredTripod`) and an option of the repertoire planner, whose cycles
:class:`TripodSteps` learns as the robot walks them. :func:`tripod_cycles` measures one cycle of
each direction under damage, for the step bank.
"""

from __future__ import annotations

import math

from hexapod_gait import GaitParameters, preset
from hexapod_navigation.core.geometry import Pose2D, wrap_angle
from hexapod_navigation.core.policy import Step
from hexapod_sim.damage import Damage
from hexapod_sim.evaluation import evaluate_displacements
from hexapod_sim.simulator import Simulator
import numpy as np

#: The firmware's eight crab directions (robot-facts.md, movement frame), in base_link.
FIRMWARE_DIRECTIONS = tuple(k * math.pi / 4 for k in range(8))


def tripod_gaits() -> list[GaitParameters]:
    """Return the control tripod in each firmware crab direction (index = direction 0..7)."""
    base = preset('control')
    return [base.replace(crab_angle=wrap_angle(a)) for a in FIRMWARE_DIRECTIONS]


def tripod_cycles(sim: Simulator, damage: Damage | None) -> np.ndarray:
    """
    Return each direction's second cycle from rest under ``damage`` (None: intact), (8, 3).

    Each (dx, dy, dyaw) in the frame the robot had when the cycle began. The second cycle,
    because the navigator walks tripod cycles back to back (the first is within 3 % of it,
    intact). Deterministic.
    """
    gaits = tripod_gaits()
    period = gaits[0].period
    damage = damage if damage is not None else Damage()  # None would keep the sim's damage
    one = evaluate_displacements(gaits, sim, period, collisions_fatal=False, failed_legs=damage)
    two = evaluate_displacements(
        gaits, sim, 2 * period, collisions_fatal=False, failed_legs=damage
    )
    out = np.zeros((len(gaits), 3))
    for k, (a, b) in enumerate(zip(one, two)):
        if not (a.valid and b.valid):
            continue  # an unstable rollout: no motion (the cycle is learned as it is walked)
        c, s = math.cos(a.yaw), math.sin(a.yaw)
        dx, dy = b.x - a.x, b.y - a.y
        out[k] = (c * dx + s * dy, -s * dx + c * dy, wrap_angle(b.yaw - a.yaw))
    return out


def steered_direction(pose: Pose2D, goal: tuple[float, float]) -> int:
    """Return the firmware crab direction (0..7) nearest the goal's bearing from ``pose``."""
    bearing = wrap_angle(math.atan2(goal[1] - pose.y, goal[0] - pose.x) - pose.yaw)
    return round(bearing / (math.pi / 4)) % 8


class TripodSteps:
    """
    The steered tripod's eight crab directions as candidate steps, one gait cycle each.

    What one cycle moves the robot is learned as it walks: the displacements seen, in the frame
    of their crab direction (along, across, turn), pooled over the directions, and per direction.
    A direction's estimate is its own mean shrunk toward the pooled one, which is itself shrunk
    toward ``prior`` times the commanded stride (``PRIOR_WEIGHT`` cycles' worth each), so one
    cycle walked on a damage tells every direction about it. Given a prior per direction (a
    damage bank's cycles, mixed by how well each damage explains what was walked:
    :meth:`CorrectionGP.tripod_prior`), a direction's own mean shrinks toward that instead, with
    ``bank_weight`` cycles' worth.
    """

    PRIOR_WEIGHT = 1.0

    def __init__(self, prior: float = 1.0, bank_weight: float = 1.0) -> None:
        base = preset('control')
        self.bank_weight = bank_weight  # cycles' worth of a direction's prior from a bank
        self.gaits = tripod_gaits()
        self.period = base.period
        self._angles = np.array([g.crab_angle for g in self.gaits])
        stride = np.array([prior * base.body_velocity * base.period, 0.0, 0.0])
        self._pooled = [stride * self.PRIOR_WEIGHT, self.PRIOR_WEIGHT]
        self._sums = np.zeros((len(self.gaits), 3))
        self._counts = np.zeros(len(self.gaits))

    def displacement(self, prior: np.ndarray | None = None) -> np.ndarray:
        """
        Return each direction's expected cycle (dx, dy, dyaw) in the robot's frame, (8, 3).

        ``prior`` (8, 3), robot frame: each direction's expected cycle before it is walked
        (None: the pooled estimate).
        """
        c, s = np.cos(self._angles), np.sin(self._angles)
        weight = self.PRIOR_WEIGHT
        if prior is None:
            toward = (self._pooled[0] / self._pooled[1])[None, :]
        else:
            weight = self.bank_weight
            p = np.asarray(prior, dtype=float)
            toward = np.column_stack(
                [c * p[:, 0] + s * p[:, 1], -s * p[:, 0] + c * p[:, 1], p[:, 2]]
            )
        local = (self._sums + toward * weight) / (self._counts[:, None] + weight)
        return np.column_stack(
            [c * local[:, 0] - s * local[:, 1], s * local[:, 0] + c * local[:, 1], local[:, 2]]
        )

    def observe(self, k: int, moved: tuple[float, float, float]) -> None:
        """Learn that a cycle of direction ``k`` moved (dx, dy, dyaw) in the robot's frame."""
        c, s = math.cos(self._angles[k]), math.sin(self._angles[k])
        dx, dy, dyaw = moved
        local = np.array([c * dx + s * dy, -s * dx + c * dy, dyaw])
        self._pooled[0] = self._pooled[0] + local
        self._pooled[1] += 1.0
        self._sums[k] += local
        self._counts[k] += 1.0


class SteeredTripod:
    """
    Baseline: the control tripod steered toward the goal every cycle, as the firmware can walk.

    Each cycle it walks the crab direction of the eight nearest the goal's bearing.
    """

    def __init__(self) -> None:
        self._gaits = tripod_gaits()

    def next_step(
        self,
        pose: Pose2D,
        goal: tuple[float, float],
        playing: GaitParameters | None = None,
        switch_time: float = 0.0,
    ) -> Step:
        """Return one cycle toward the goal (after the body's transition, if it turns)."""
        gait = self._gaits[steered_direction(pose, goal)]
        reach = gait.body_velocity * gait.period
        heading = pose.yaw + gait.crab_angle
        predicted = Pose2D(
            pose.x + reach * math.cos(heading), pose.y + reach * math.sin(heading), pose.yaw
        )
        return Step(gait, gait.period + (0.0 if gait is playing else switch_time), predicted)

    def observe(self, step: Step, start: Pose2D, end: Pose2D, completed: bool) -> float | None:
        """Nothing is learned; return the cycle's error against the commanded stride."""
        return end.distance_to(step.predicted.x, step.predicted.y) if completed else None

    def avoid(self, step: Step) -> None:
        """Nothing: the baseline has no other gait (it walks on, the guard catching each tilt)."""
