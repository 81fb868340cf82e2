# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Reaching a goal with a damaged robot, learning while it walks, with no resets (ROS-free).

Reset-free trial and error (Chatzilygeroudis, Vassiliades and Mouret 2018), adapted to a
crab-walking hexapod:

* a :class:`~hexapod_navigation.core.repertoire.Repertoire` of omnidirectional gaits, each indexed
  by the displacement one step (one execution, ``step_duration`` s) gives the intact robot;
* :class:`~hexapod_navigation.core.correction.CorrectionGP`: one Gaussian process per displacement
  dimension (x, y, heading) over the repertoire's descriptor, learning from every step how the
  damage changes the steps;
* a planner (:class:`RepertoirePolicy`) that picks the step whose predicted end lies nearest
  the goal, from the pose the robot is actually in;
* :func:`hexapod_navigation.core.episode.run_episode` walks a body with them (the loop, its
  bodies).

The baseline :class:`~hexapod_navigation.core.tripod.SteeredTripod` is what the robot's firmware
can do: the control tripod, steered every cycle toward the goal in the nearest of its eight crab
directions; the planner weighs its next cycle too
(:class:`~hexapod_navigation.core.tripod.TripodSteps`). Poses:
:mod:`hexapod_navigation.core.geometry`; what a policy is: :mod:`hexapod_navigation.core.policy`;
the settings: :mod:`hexapod_navigation.core.config`.
"""

from __future__ import annotations

import math

from hexapod_gait import GaitParameters
from hexapod_navigation.core.config import NavigationConfig
from hexapod_navigation.core.correction import CorrectionGP
from hexapod_navigation.core.geometry import Pose2D
from hexapod_navigation.core.policy import Step
from hexapod_navigation.core.repertoire import Repertoire
from hexapod_navigation.core.step_bank import StepBank
from hexapod_navigation.core.tripod import steered_direction, TripodSteps
from hexapod_sim.damage import Damage
import numpy as np


def time_to_goal(
    start: tuple[float, float],
    ends: np.ndarray,
    goal: tuple[float, float],
    radius: float,
    step_time: float,
    switch: np.ndarray,
    speed: float | np.ndarray,
) -> np.ndarray:
    """
    Return each step's expected time [s] until the robot is within ``radius`` of ``goal``.

    A step (row of ``ends`` (n, 2), where it ends) first spends ``switch`` (n,) s changing gait,
    then walks ``step_time`` s along the straight line from ``start`` to its end. If that line
    enters the goal circle, the time is the switch and the time into the step at which it does;
    otherwise the switch, the whole step, and the rest of the way from its end at ``speed`` m/s
    (one for every step, or each its own).
    """
    p0 = np.asarray(start, dtype=float)
    g = np.asarray(goal, dtype=float)
    ends = np.asarray(ends, dtype=float)
    d = ends - p0  # (n, 2): the step's chord
    length2 = np.maximum(np.sum(d * d, axis=1), 1e-12)
    # the chord's point nearest the goal, as a fraction f of the step
    f = np.clip((d @ (g - p0)) / length2, 0.0, 1.0)
    miss2 = np.sum((p0 + f[:, None] * d - g) ** 2, axis=1)
    inside = miss2 <= radius**2
    # walking back from the nearest point to where the chord enters the circle
    back = np.sqrt(np.maximum(radius**2 - miss2, 0.0) / length2)
    arrive = np.maximum(f - back, 0.0) * step_time
    after = np.hypot(*(g - ends).T)
    rest = step_time + np.maximum(after - radius, 0.0) / np.maximum(speed, 1e-6)
    return np.asarray(switch, dtype=float) + np.where(inside, arrive, rest)


def rest_speeds(
    ends: np.ndarray,
    goal: tuple[float, float],
    radius: float,
    progress: np.ndarray,
    best: float,
    step_time: float,
    switch_time: float,
) -> np.ndarray:
    """
    Return each step's average speed [m/s] over the rest of the way from its end (``ends`` (n, 2)).

    The rest is walked by the step's own gait, ``progress`` (n,) m toward the goal per
    ``step_time`` s, or after a ``switch_time`` s transition by the gait that makes ``best`` m,
    whichever reaches the goal circle (``radius``) sooner.
    """
    after = np.maximum(np.hypot(goal[0] - ends[:, 0], goal[1] - ends[:, 1]) - radius, 0.0)
    own = after * step_time / np.maximum(progress, 1e-3)
    other = switch_time + after * step_time / best
    fast = best / step_time  # where nothing is left, any speed gives the same time
    return np.where(after > 0, after / np.maximum(np.minimum(own, other), 1e-12), fast)


class RepertoirePolicy:
    """
    The repertoire planner, with (``config.learn``) or without the GP correction.

    ``hypotheses``: a damage bank's step tables
    (:class:`hexapod_navigation.core.step_bank.StepBank`'s ``steps``), weighed when
    ``config.use_bank`` and ``config.learn``.
    """

    def __init__(
        self,
        repertoire: Repertoire,
        config: NavigationConfig,
        hypotheses: np.ndarray | None = None,
        tripods: np.ndarray | None = None,
        reported: int | None = None,
        tilts: np.ndarray | None = None,
    ) -> None:
        self.repertoire = repertoire
        self.config = config
        use = config.use_bank and config.learn and hypotheses is not None
        self.gp = CorrectionGP(
            repertoire,
            config,
            hypotheses if use else None,
            tripods if use and config.tripod_bank != 'off' else None,
            reported if use else None,
        )
        self.tripod = TripodSteps(config.tripod_prior, config.tripod_bank_weight)
        self._goal: tuple[float, float] | None = None  # of the last step chosen
        self._made: list[tuple[float, float]] = []  # repertoire steps: (progress [m], time [s])
        self._gaits: dict[int, GaitParameters] = {}
        self.allowed = repertoire.min_stance() >= config.min_stance_legs
        self._avoided_tripods: set[int] = set()  # crab directions that tilted past the guard
        # (h, n) each step's largest tilt under each hypothesis of the bank (NaN: not measured)
        self.tilts = tilts if use and config.expected_tilt_limit < math.pi else None
        if not self.allowed.any():
            raise ValueError(
                f'no repertoire gait keeps {config.min_stance_legs} feet on the ground throughout'
            )

    @classmethod
    def with_bank(
        cls,
        repertoire: Repertoire,
        config: NavigationConfig,
        bank: StepBank | None,
        reported: Damage | None = None,
    ) -> RepertoirePolicy:
        """
        Return the policy weighing ``bank``'s steps and tripod cycles (None: no bank).

        ``reported``: the damage the robot reported (its dead servos), favoured as
        ``config.prior_reported`` says when the bank models it (:meth:`StepBank.index_of`).
        """
        if bank is None:
            return cls(repertoire, config)
        row = bank.index_of(reported) if reported is not None else None
        return cls(
            repertoire,
            config,
            bank.steps,
            bank.tripods(),
            None if row is None else row + 1,
            bank.tilt,
        )

    def _upright(self) -> np.ndarray:
        """Return which steps may be taken: allowed, and not expected to tilt past the limit."""
        if self.tilts is None:
            return self.allowed
        end = 1 + len(self.tilts)
        w = self.gp.weights[1:end]  # the bank's damages (intact is first)
        expected = np.nansum(w[:, None] * self.tilts, axis=0) / max(float(w.sum()), 1e-12)
        upright = self.allowed & ~(expected > self.config.expected_tilt_limit)
        return upright if upright.any() else self.allowed

    def next_step(
        self,
        pose: Pose2D,
        goal: tuple[float, float],
        playing: GaitParameters | None = None,
        switch_time: float = 0.0,
    ) -> Step:
        """
        Return the best step from ``pose`` by ``config.planner`` (one step ahead).

        Both planners move each predicted end ``optimism`` standard deviations toward the goal
        (a lower confidence bound on the distance left). 'nearest' takes the step that then ends
        nearest the goal; 'time' the one with the least expected time to it
        (:func:`time_to_goal`), the steered tripod's cycles included (``tripod_option``).
        """
        mean, var = self.gp.predict()
        allowed = self._upright()
        c, s = math.cos(pose.yaw), math.sin(pose.yaw)
        ex = pose.x + c * mean[:, 0] - s * mean[:, 1]
        ey = pose.y + s * mean[:, 0] + c * mean[:, 1]
        left = np.hypot(goal[0] - ex, goal[1] - ey)
        optimism = self.config.optimism + self.config.unknown_optimism * self.gp.unknown_weight
        shift = optimism * np.sqrt(var[:, 0] + var[:, 1])
        playing_row = next((i for i, g in self._gaits.items() if g is playing), -1)
        switch = np.full(len(mean), float(switch_time))
        if playing_row >= 0:
            switch[playing_row] = 0.0
        if self.config.planner == 'nearest':
            cost = left - shift
            i = int(np.argmin(np.where(allowed, cost, np.inf)))
            return self._repertoire_step(i, pose, mean, switch)
        # the end moved toward the goal by the optimism's shift (no further than the goal)
        pull = np.minimum(shift, left) / np.maximum(left, 1e-12)
        ends = np.column_stack([ex + pull * (goal[0] - ex), ey + pull * (goal[1] - ey)])
        to_goal = np.array([goal[0] - pose.x, goal[1] - pose.y])
        unit = to_goal / max(float(np.hypot(*to_goal)), 1e-12)
        if self.config.rest_speed == 'toward':
            # each step's progress toward the goal from here (the chord's projection); a
            # floor of 1 mm per step: no step that heads for the goal is a big cost, not an
            # infinite one
            progress = (ex - pose.x) * unit[0] + (ey - pose.y) * unit[1]
            best = max(float(np.max(progress[allowed])), 1e-3)
        else:
            best = float(np.max(np.hypot(mean[:, 0], mean[:, 1])[allowed]))
        radius = self.config.aim * self.config.tolerance
        step = self.repertoire.step_duration
        speed: float | np.ndarray = best / step
        if self.config.rest_switch and self.config.rest_speed == 'toward':
            speed = rest_speeds(ends, goal, radius, progress, best, step, switch_time)
        cost = time_to_goal((pose.x, pose.y), ends, goal, radius, step, switch, speed)
        i = int(np.argmin(np.where(allowed, cost, np.inf)))
        self._goal = goal
        if self.config.tripod_option:
            tripod = self._tripod_step(pose, goal, playing, switch_time, unit, radius, cost[i])
            if tripod is not None:
                return tripod
        return self._repertoire_step(i, pose, mean, switch)

    def _tripod_step(
        self,
        pose: Pose2D,
        goal: tuple[float, float],
        playing: GaitParameters | None,
        switch_time: float,
        unit: np.ndarray,
        radius: float,
        best_cost: float,
    ) -> Step | None:
        """
        Return the steered tripod's next cycle when it beats the repertoire's best step.

        The cycle is in the crab direction nearest the goal's bearing, as the baseline walks it,
        where the robot has been making such cycles go; its time is the rest of the way at the
        tripod's own pace, if the robot commits to it. It is a candidate once the repertoire's
        last steps made less progress than that pace (the repertoire has had its chance to
        learn the damage). None: the repertoire's step stands.
        """
        k = steered_direction(pose, goal)
        if k in self._avoided_tripods:
            return None
        # 'evidence': a walked step or cycle (tripod_reported: or a report of a damage the
        # bank models, before anything is walked)
        told = self.config.tripod_reported and self.gp.reported is not None
        bank = self.config.tripod_bank == 'always' or self.gp.evidence > 0 or told
        cycle = self.tripod.displacement(self.gp.tripod_prior() if bank else None)[k]
        c, s = math.cos(pose.yaw), math.sin(pose.yaw)
        dx, dy = cycle[0], cycle[1]
        end = np.array([[pose.x + c * dx - s * dy, pose.y + s * dx + c * dy]])
        gait = self.tripod.gaits[k]
        tripod_switch = 0.0 if gait is playing else float(switch_time)
        pace = max(float((end[0] - (pose.x, pose.y)) @ unit), 1e-3) / self.tripod.period
        tripod_cost = time_to_goal(
            (pose.x, pose.y), end, goal, radius, self.tripod.period, [tripod_switch], pace
        )[0]
        n = self.config.tripod_after
        made = self._made[-n:] if n else []
        lagging = len(made) == n and sum(p for p, _ in made) <= pace * sum(t for _, t in made)
        if lagging and tripod_cost < best_cost:
            return Step(gait, self.tripod.period + tripod_switch, pose.moved(*cycle), tripod=k)
        return None

    def _repertoire_step(self, i: int, pose: Pose2D, mean: np.ndarray, switch: np.ndarray) -> Step:
        if i not in self._gaits:
            self._gaits[i] = self.repertoire.gait(i)
        predicted = pose.moved(*mean[i])
        return Step(self._gaits[i], self.repertoire.step_duration + switch[i], predicted, i)

    def observe(self, step: Step, start: Pose2D, end: Pose2D, completed: bool) -> float | None:
        """Learn a whole step (a cut-short one teaches nothing); return its prediction error."""
        if not completed:
            return None
        error = end.distance_to(step.predicted.x, step.predicted.y)
        if step.tripod >= 0:
            moved = start.relative(end)
            self.tripod.observe(step.tripod, moved)
            if self.config.learn:
                self.gp.add_tripod(step.tripod, moved)
            return error
        if self._goal is not None:  # the progress it made toward the goal it was taken for
            g = self._goal
            made = start.distance_to(*g) - end.distance_to(*g)
            self._made.append((made, step.duration))
        if self.config.learn:
            self.gp.add(step.index, start.relative(end))
        return error

    def avoid(self, step: Step) -> None:
        """Never take ``step`` again (it tilted past the guard), unless it is the last one left."""
        if step.tripod >= 0:
            self._avoided_tripods.add(step.tripod)
        elif step.index >= 0 and np.count_nonzero(self.allowed) > 1:
            self.allowed[step.index] = False
