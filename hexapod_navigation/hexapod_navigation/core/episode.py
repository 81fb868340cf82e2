# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A navigation episode: the loop that walks a body toward a goal step by step (ROS-free).

:func:`run_episode` is shared by the experiment (:class:`SimBody`, a simulator) and the
``navigate`` action (a body over the ROS graph, :mod:`hexapod_navigation.ros.bodies`). It stops as
soon as the robot is within the tolerance, the walking time is spent, the robot leaves the arena,
or the caller cancels. The planners it asks for steps are in
:mod:`hexapod_navigation.core.planner`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import enum
import json
import math
from typing import Callable, Protocol, Sequence

from hexapod_gait import build_joint_table, GaitParameters, preset, standing_gait
from hexapod_gait.trajectory import POSE_TRANSITION_S, transition
from hexapod_navigation.core.config import NavigationConfig
from hexapod_navigation.core.geometry import Pose2D
from hexapod_navigation.core.policy import Policy
from hexapod_sim.simulator import Simulator, TIP_OVER_DEG
import numpy as np


# -- bodies and the episode --------------------------------------------------------------------
@dataclass(frozen=True)
class StepOutcome:
    """What one step did."""

    start: Pose2D
    end: Pose2D
    elapsed: float  # s walked
    completed: bool  # walked the whole duration (not stopped early)
    path: tuple[Pose2D, ...]  # poses sampled during the step, end included
    tilted: bool = False  # stopped by the tip guard (the body tilted past it), then stood


class Body(Protocol):
    """
    The robot as the navigator sees it (a simulator, or the ROS graph).

    ``switch_time`` [s]: how long a new gait spends moving the legs to its first pose before it
    walks, counted as walking time (0 where that happens outside the walking time);
    ``playing``: the gait a next step would simply go on with (None: the body stands).
    """

    switch_time: float
    playing: GaitParameters | None

    def pose(self) -> Pose2D:
        """Return the current pose estimate in odom."""

    def walk(
        self, gait: GaitParameters, duration: float, stop: Callable[[Pose2D], bool]
    ) -> StepOutcome:
        """Walk ``gait`` for ``duration`` s (a switch included), or until ``stop(pose)``."""

    def halt(self) -> None:
        """Stop walking (stand)."""


class Outcome(enum.Enum):
    """How a navigation ended."""

    REACHED = 'reached'
    TIME_LIMIT = 'time_limit'
    LEFT_ARENA = 'left_arena'
    CANCELED = 'canceled'
    FAILED = 'failed'  # the body could not walk (see the reason)


@dataclass(frozen=True)
class Feedback:
    """Progress after each step."""

    pose: Pose2D
    distance_left: float  # m
    steps: int
    prediction_error: float  # m, of the last whole step (NaN if none yet)
    walking_time: float  # s so far
    tilted: bool = False  # the tip guard stopped the last step (the policy avoids it since)


@dataclass
class NavigationResult:
    """The end of one goal."""

    outcome: Outcome
    reason: str
    walking_time: float  # s
    path_length: float  # m
    steps: int
    start: Pose2D
    end: Pose2D
    goal: tuple[float, float]
    path: list[Pose2D] = field(default_factory=list)
    prediction_errors: list[float] = field(default_factory=list)

    @property
    def reached(self) -> bool:
        """Return True if the goal was reached."""
        return self.outcome is Outcome.REACHED

    @property
    def efficiency(self) -> float:
        """Straight-line distance from start to end / path length (NaN if it did not move)."""
        direct = self.start.distance_to(self.end.x, self.end.y)
        return direct / self.path_length if self.path_length > 0 else float('nan')


class BodyFailure(RuntimeError):
    """The body could not take a step (the robot refused, a topic went silent, it tipped over)."""


#: s: how long a body stands after its tip guard stopped a step (walking time: the robot waits)
GUARD_STAND_S = 1.0


def past_guard(roll: float, pitch: float, guard: float) -> bool:
    """Whether roll or pitch [rad] is past the tip guard ``guard`` [rad]."""
    return max(abs(roll), abs(pitch)) > guard


def tipped_over(roll: float, pitch: float) -> str:
    """Say how the robot tipped over ('' if it stands): roll and pitch in radians."""
    r, p = math.degrees(roll), math.degrees(pitch)
    if max(abs(r), abs(p)) > TIP_OVER_DEG:
        return f'the robot tipped over (roll {r:.0f} deg, pitch {p:.0f} deg)'
    return ''


def path_length(path: Sequence[Pose2D]) -> float:
    """Return the length of a sampled path [m]."""
    return float(sum(a.distance_to(b.x, b.y) for a, b in zip(path, path[1:])))


def run_episode(
    body: Body,
    policy: Policy,
    goal: tuple[float, float],
    config: NavigationConfig,
    cancelled: Callable[[], bool] = lambda: False,
    feedback: Callable[[Feedback], None] | None = None,
) -> NavigationResult:
    """
    Walk toward ``goal`` (odom), step by step; return how it ended.

    It ends when the robot is within the tolerance, the walking time is spent, the robot leaves
    the arena, or the caller cancels. The body is left standing.
    """
    start = body.pose()
    path = [start]
    errors: list[float] = []
    walked, steps = 0.0, 0
    tol = config.tolerance

    def outside(p: Pose2D) -> bool:
        return config.arena is not None and max(abs(p.x), abs(p.y)) > config.arena

    def finish(outcome: Outcome, reason: str) -> NavigationResult:
        body.halt()
        return NavigationResult(
            outcome, reason, walked, path_length(path), steps, start, path[-1], goal, path, errors
        )

    while True:
        pose = path[-1]
        if pose.distance_to(*goal) <= tol:
            return finish(Outcome.REACHED, f'within {tol:g} m of the goal')
        if outside(pose):
            return finish(Outcome.LEFT_ARENA, f'left the arena (|x|, |y| <= {config.arena:g} m)')
        if cancelled():
            return finish(Outcome.CANCELED, 'canceled')
        left = config.time_limit - walked
        if left <= 1e-9:
            return finish(
                Outcome.TIME_LIMIT,
                f'{config.time_limit:g} s of walking spent; {pose.distance_to(*goal):.2f} m left',
            )
        step = policy.next_step(pose, goal, body.playing, body.switch_time)
        try:
            outcome = body.walk(
                step.gait,
                min(step.duration, left),
                lambda p: p.distance_to(*goal) <= tol or outside(p) or cancelled(),
            )
        except BodyFailure as exc:
            return finish(Outcome.FAILED, str(exc))
        walked += outcome.elapsed
        steps += 1
        path.extend(outcome.path)
        completed = outcome.completed and outcome.elapsed >= step.duration - 1e-9
        if outcome.tilted:
            policy.avoid(step)
        error = policy.observe(step, outcome.start, outcome.end, completed)
        if error is not None:
            errors.append(error)
        if feedback is not None:
            feedback(
                Feedback(
                    outcome.end,
                    outcome.end.distance_to(*goal),
                    steps,
                    errors[-1] if errors else float('nan'),
                    walked,
                    outcome.tilted,
                )
            )


class SimBody:
    """
    A :class:`Body` on a simulator: steps follow each other with no reset.

    A new gait starts with the legs moving from wherever they are to its table's first row in
    POSE_TRANSITION_S (as the robot's firmware does); the same gait again needs no transition,
    but starts its one-cycle table from the first row again (where a step is not a whole number
    of the gait's cycles, its phase jumps there). The transition is walking time too. Poses are
    sampled every ``sample_period`` s. A step that tilts the body past ``tip_guard`` rad (roll or
    pitch) is stopped, and the robot stands for GUARD_STAND_S (walking time too).
    """

    switch_time = POSE_TRANSITION_S

    def __init__(
        self, sim: Simulator, sample_period: float = 0.05, tip_guard: float = math.pi
    ) -> None:
        self.sim = sim
        self.tip_guard = tip_guard
        self.every = max(1, int(round(sample_period / sim.dt)))
        self._tables: dict[str, tuple[object, int, np.ndarray]] = {}
        self._stand = standing_gait()
        self._current: GaitParameters | None = None

    @property
    def playing(self) -> GaitParameters | None:
        """Return the gait that a next step with the same gait goes on with (None: standing)."""
        return self._current

    def start(self, gait: GaitParameters | None = None) -> None:
        """Put the robot at the origin, standing in the first pose of ``gait`` (or the tripod)."""
        table = build_joint_table(gait or preset('control'), rate=1.0 / self.sim.dt)
        self.sim.reset(table.positions[0])
        self._current = None

    def pose(self) -> Pose2D:
        """Return where the base is, in the plane (ground truth)."""
        position, _ = self.sim.base_pose()
        return Pose2D(float(position[0]), float(position[1]), float(self.sim.base_euler()[2]))

    def _rows(self, gait: GaitParameters) -> tuple[object, int, np.ndarray]:
        # keyed by the gait's values: an id() would be reused by a later gait once this one is
        # collected, and would play that gait the wrong table
        key = json.dumps(gait.to_dict(), sort_keys=True)
        if key not in self._tables:
            table = build_joint_table(gait, rate=1.0 / self.sim.dt)
            rows = self.sim.prepare_rows(table.positions, table.velocities)
            self._tables[key] = (rows, len(table), table.positions[0])
        return self._tables[key]

    def walk(
        self, gait: GaitParameters, duration: float, stop: Callable[[Pose2D], bool]
    ) -> StepOutcome:
        """Play ``gait`` for ``duration`` s (or until ``stop``), sampling the pose."""
        outcome = self._play(gait, duration, stop)
        if not outcome.tilted:
            return outcome
        stood = self._play(self._stand, GUARD_STAND_S, lambda _: False, guarded=False)
        return StepOutcome(
            outcome.start,
            stood.end,
            outcome.elapsed + stood.elapsed,
            False,
            outcome.path + stood.path,
            tilted=True,
        )

    def _play(
        self,
        gait: GaitParameters,
        duration: float,
        stop: Callable[[Pose2D], bool],
        guarded: bool = True,
    ) -> StepOutcome:
        rows, n_rows, first = self._rows(gait)
        start = self.pose()
        path: list[Pose2D] = []
        moving, n_move = None, 0
        if gait is not self._current:
            q = transition(self.sim.joint_states()[0], first, POSE_TRANSITION_S, 1.0 / self.sim.dt)
            moving, n_move = self.sim.prepare_rows(q, np.zeros_like(q)), len(q)  # rows: opaque
        self._current = gait
        n_steps = int(round(duration / self.sim.dt))
        k = 0
        tilted = False
        while k < n_steps:
            if k < n_move:
                self.sim.apply_row(moving, k)
            else:
                self.sim.apply_row(rows, (k - n_move) % n_rows)
            report = self.sim.step()
            if report.unstable:
                raise BodyFailure('the physics became unstable')
            k += 1
            if k % self.every == 0 or k == n_steps:
                path.append(self.pose())
                roll, pitch, _ = self.sim.base_euler()
                fallen = tipped_over(roll, pitch)
                if fallen:
                    raise BodyFailure(fallen)
                tilted = guarded and past_guard(roll, pitch, self.tip_guard)
                if k < n_steps and (tilted or stop(path[-1])):
                    break
        end = path[-1] if path else start
        done = k >= n_steps and not tilted
        return StepOutcome(start, end, k * self.sim.dt, done, tuple(path), tilted)

    def halt(self) -> None:
        """Stand: command the standing pose (nothing is simulated until the next walk)."""
        rows, _, _ = self._rows(self._stand)
        self.sim.apply_row(rows, 0)
        self._current = None
