# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The navigator's bodies through a ROS graph, without ROS: sim_node, or bridge_node (the robot).

Like :mod:`hexapod_adapt.online.trials`, these are built over a small port
(:class:`NavigationPort`, implemented over rclpy by the node) and a :class:`PoseLog` the node fills
from its pose source: ``odom`` (sim_node's ground truth, or the bridge's IMU odometry) or an
external pose topic (motion capture, a camera).

``SimGraphBody``    publish the gait; sim_node plays it from where the robot stands; the step lasts
                    ``duration`` s of the pose source's time and stops early when asked; then
                    the robot stands while the next step is planned (sim_node may run faster
                    than real time: a gait left on would walk on unplanned);
``RobotGraphBody``  upload the gait through bridge_node, walk one trial of the bridge's trial
                    duration, and compose the pose from each trial's odometry (the trial's
                    displacement in the frame the robot started it in), unless an external pose
                    source is given.
"""

from __future__ import annotations

from dataclasses import dataclass
import math
import time
from typing import Callable, Protocol

from hexapod_adapt import SampleLog, TrialAborted, Waiter
from hexapod_gait import GaitParameters, standing_gait
from hexapod_navigation.core.episode import BodyFailure, past_guard, StepOutcome, tipped_over
from hexapod_navigation.core.geometry import Pose2D


@dataclass(frozen=True)
class PoseSample:
    """One pose message."""

    stamp_ns: int  # header stamp (sim time in simulation)
    pose: Pose2D
    received: float  # time.monotonic() when it arrived
    roll: float = 0.0  # rad (tip-over detection)
    pitch: float = 0.0


@dataclass(frozen=True)
class StepResult:
    """One of bridge_node's trial results (``trial_result``) as a robot step reads it."""

    valid: bool  # walked and measured whole: its displacement may be used
    reason: str  # why not ('' when valid)
    pose: Pose2D  # displacement over the walk, in the frame the robot started it in
    received: float  # time.monotonic() when it arrived


class PoseLog(SampleLog[PoseSample]):
    """The poses received so far from the pose source."""

    def first_at_or_after(self, stamp_ns: int) -> PoseSample | None:
        """Return the earliest pose kept whose stamp is at or after ``stamp_ns``, if any."""
        found = None
        for sample in reversed(self.snapshot()):  # newest first: stop at the first older one
            if sample.stamp_ns < stamp_ns:
                break
            found = sample
        return found


class NavigationPort(Protocol):
    """What a navigation step does to the graph (the node implements it over rclpy)."""

    def publish_gait(self, gait: GaitParameters) -> int:
        """Publish a gait on gait/parameters; return its unique stamp [ns]."""

    def active_stamp(self) -> int | None:
        """Return the stamp of the gait sim_node plays (sim/active_trajectory)."""

    def activated_at(self, stamp: int) -> int | None:
        """Return the simulation time [ns] the gait stamped ``stamp`` took effect (activations)."""

    def upload(self, gait: GaitParameters, timeout: float) -> tuple[bool, str]:
        """Upload a gait through bridge_node: (confirmed, its message)."""

    def start_trial(self) -> tuple[bool, str]:
        """Start a trial on the robot."""

    def stop_trial(self) -> tuple[bool, str]:
        """Stop the robot's trial."""


class SimGraphBody:
    """A navigator's body through gait_node + sim_node (or any body that plays published gaits)."""

    #: sim_node switches gaits at once, and every step starts from standing (see halt)
    switch_time = 0.0
    playing = None

    def __init__(
        self,
        port: NavigationPort,
        poses: PoseLog,
        waiter: Waiter,
        timeout: float = 10.0,
        tip_guard: float = math.pi,
    ) -> None:
        self.port, self.poses, self.waiter, self.timeout = port, poses, waiter, timeout
        self.tip_guard = tip_guard  # rad: a step that tilts the body past it is stopped
        self._stand = standing_gait()

    def pose(self) -> Pose2D:
        """Return where the pose source last put the robot (waits for its first message)."""
        sample = self.poses.latest() or self.waiter.until(
            self.poses.latest, self.timeout, 'a pose (is the pose source publishing?)'
        )
        return sample.pose

    def _play(self, gait: GaitParameters) -> int:
        """Publish ``gait`` and wait until sim_node plays it; return the sim time it began [ns]."""
        stamp = self.port.publish_gait(gait)
        self.waiter.until(
            lambda: self.port.active_stamp() == stamp,
            self.timeout,
            'sim_node to play the gait (are gait_node and sim_node running?)',
        )
        return self.waiter.until(
            lambda: self.port.activated_at(stamp),
            self.timeout,
            'sim_node to say when the gait took effect (sim/activations)',
        )

    def walk(
        self, gait: GaitParameters, duration: float, stop: Callable[[Pose2D], bool]
    ) -> StepOutcome:
        """
        Play ``gait`` for ``duration`` s of the pose source's time, or until ``stop``.

        The step is timed by the simulation's clock from the moment sim_node switched to the gait,
        however late this node hears of it: its start is the first pose at or after that moment
        and its end the first at or after ``duration`` later.
        """
        try:
            began = self._play(gait)
            first = self.waiter.until(
                lambda: self.poses.first_at_or_after(began), self.timeout, 'a pose after the gait'
            )
        except TrialAborted as exc:
            raise BodyFailure(str(exc)) from None
        start, t0 = first.pose, began
        end_ns = t0 + int(round(duration * 1e9))
        path, last = [start], first
        completed = tilted = False
        while True:
            try:
                last = self.waiter.until(
                    lambda: (
                        s if (s := self.poses.latest()) and s.stamp_ns > last.stamp_ns else None
                    ),
                    self.timeout,
                    'the next pose',
                )
            except TrialAborted as exc:
                raise BodyFailure(str(exc)) from None
            path.append(last.pose)
            fallen = tipped_over(last.roll, last.pitch)
            if fallen:
                raise BodyFailure(fallen)
            if past_guard(last.roll, last.pitch, self.tip_guard):
                tilted = True
                break
            if last.stamp_ns >= end_ns:
                # the step ends at the first pose at or after its end (a late reader may have
                # heard newer ones by now)
                last = self.poses.first_at_or_after(end_ns) or last
                path[-1] = last.pose
                completed = True
                break
            if stop(last.pose):
                break
        self.halt()
        return StepOutcome(
            start, last.pose, (last.stamp_ns - t0) / 1e9, completed, tuple(path), tilted
        )

    def halt(self) -> None:
        """Stand still (the standing gait); a body that does not answer is left as it is."""
        try:
            self._play(self._stand)
        except TrialAborted:
            pass


class RobotGraphBody:
    """
    A navigator's body through bridge_node: one trial per step.

    A step starts from the newest pose (bridge_node's ``odom``, or the external source). Without an
    external source (``external`` False) it ends where the trial's result (``trial_result``: its
    displacement in the frame the robot started the trial in, and the IMU's heading change) moves
    the start: the same composition bridge_node's continuous ``odom`` makes. A step the bridge
    says was not walked and measured whole (the link lost, the robot restarted) is never used: the
    goal ends with the reason.
    """

    #: the firmware moves the legs to a gait's first pose before the trial's time starts, and
    #: every step is a trial of its own
    switch_time = 0.0
    playing = None

    def __init__(
        self,
        port: NavigationPort,
        poses: PoseLog,
        trials: SampleLog[StepResult],
        waiter: Waiter,
        trial_duration: float,
        external: bool,
        timeout: float = 10.0,
        stand_still: float = 1.0,
        sleep: Callable[[float], None] = time.sleep,
    ) -> None:
        self.port, self.poses, self.trials, self.waiter = port, poses, trials, waiter
        self.trial_duration, self.external, self.timeout = trial_duration, external, timeout
        self.stand_still, self.sleep = stand_still, sleep

    def pose(self) -> Pose2D:
        """Return where the robot is: the external source's newest pose, or bridge_node's odom."""
        source = 'the external pose topic' if self.external else "bridge_node's odom"
        sample = self.poses.latest() or self.waiter.until(
            self.poses.latest, self.timeout, f'a pose from {source}'
        )
        return sample.pose

    def walk(
        self, gait: GaitParameters, duration: float, stop: Callable[[Pose2D], bool]
    ) -> StepOutcome:
        """Upload ``gait`` and walk one trial (the bridge's ``trial_duration``)."""
        try:
            ok, message = self.port.upload(gait, self.timeout)
            if not ok:
                raise BodyFailure(f'the robot did not take the gait: {message}')
            self.sleep(max(0.0, self.stand_still))  # a clean IMU rest window
            start = self.pose()
            ok, message = self.port.start_trial()
            if not ok:
                raise BodyFailure(f'bridge_node did not start the trial: {message}')
            started = time.monotonic()
            trial = self.waiter.until(
                lambda: self.trials.received_after(started),
                self.trial_duration + self.timeout,
                "the trial's result from bridge_node (trial_result)",
            )
        except TrialAborted as exc:
            raise BodyFailure(str(exc)) from None
        if not trial.valid:
            raise BodyFailure(f'the step was not walked and measured whole: {trial.reason}')
        if self.external:
            end = self.pose()
        else:
            d = trial.pose
            end = start.moved(d.x, d.y, d.yaw)
        return StepOutcome(
            start, end, self.trial_duration, duration >= self.trial_duration, (end,)
        )

    def halt(self) -> None:
        """Stop the robot's trial (it stands after a trial anyway)."""
        try:
            self.port.stop_trial()
        except TrialAborted:
            pass
