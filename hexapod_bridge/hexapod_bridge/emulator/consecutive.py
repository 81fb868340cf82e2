# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
An emulated robot walking trial after trial with no reset, measured as bridge_node measures it.

The bridge's procedure, in one process and on emulated time: upload, stand still (1 s, as
adapt_node and navigate_node do), open the IMU window 0.3 s before the start (pre_trial_buffer),
close it settle_time (0.5 s) after the robot reports the walk done, or later while the body
still moves (at most settle_time_max). Real bytes through the link,
the firmware model and the Xbus parser; the simulator's pose is the truth.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
import math
from typing import Sequence

from hexapod_bridge.emulator.firmware import ImuNoise, RobotFirmware
from hexapod_bridge.emulator.native import NativeRobotFirmware
from hexapod_bridge.link import RobotLink
from hexapod_bridge.odometry import ChainedPose, TrialOdometry
from hexapod_bridge.protocol import extension as ext
from hexapod_bridge.protocol.xbus import MTData, XbusParser
from hexapod_bridge.station import StationConfig
from hexapod_sim import Simulator

#: The rest after a walk before the odometry window closes: bridge_node's settings
REST_MIN, REST_MAX = StationConfig().settle_time, StationConfig().settle_time_max


@dataclass(frozen=True)
class MeasuredTrial:
    """One trial: the simulator's truth and the IMU estimate, in the frame the trial started in."""

    true_speed: float  # m/s along the walking direction (the firmware's record)
    estimated_speed: float
    true_move: tuple[float, float, float]  # dx, dy [m], heading change [rad]
    estimated_move: tuple[float, float, float]


class ConsecutiveTrials:
    """One emulated robot walking trial after trial with no reset, as on the real robot."""

    def __init__(
        self,
        sim: Simulator,
        seed: int,
        noise: ImuNoise | None = ImuNoise(),
        leg_map: Sequence[int] = ext.IDENTITY_LEG_MAP,
        firmware: str = 'python',
        robot_leg_map: Sequence[int] | None = None,
    ) -> None:
        """
        ``leg_map``: bridge_node's; ``robot_leg_map`` the robot's own numbering (default the same).

        ``firmware``: 'python' (the model) or 'native' (the C++ module).
        """
        self.sim = sim
        robot_map = leg_map if robot_leg_map is None else robot_leg_map
        if firmware == 'native':
            self.fw = NativeRobotFirmware(sim, imu_noise=noise, seed=seed, leg_map=robot_map)
        else:
            self.fw = RobotFirmware(sim=sim, imu_noise=noise, seed=seed, leg_map=robot_map)
        self.link = RobotLink(leg_map=leg_map)
        self.xp, self.history = XbusParser(), deque(maxlen=31)
        self.t = 0.0
        self.odometry: TrialOdometry | None = None
        self.link.arm(True, self.t)

    def step(self) -> None:
        """Advance the link, the firmware and the IMU parser by 2 ms."""
        self.t += 0.002
        for frame in self.link.poll(self.t):
            self.fw.receive(frame, self.t)
        radio, imu = self.fw.advance(self.t)
        self.link.receive(radio, self.t)
        for m in self.xp.feed(imu):
            if isinstance(m, MTData):
                sample = (m.counter / 100.0, m.acc, m.euler)
                self.history.append(sample)
                if self.odometry is not None:
                    self.odometry.add(*sample)

    def _pose(self) -> tuple[float, float, float]:
        position, _ = self.sim.base_pose()
        return float(position[0]), float(position[1]), float(self.sim.base_euler()[2])

    def measure(self, gait, duration: float = 5.0, settle: float = 0.0) -> MeasuredTrial:
        """
        Upload ``gait``, stand 1 s, walk one trial of ``duration`` s; return what happened.

        ``settle`` > 0: a settled trial, as the bridge's ``trial_settle`` runs it: the robot walks
        ``settle + duration`` s and both speeds are of the last ``duration`` s (the truth from the
        simulator's pose when the walk has gone on ``settle`` s).
        """
        upload = self.link.upload(gait)
        while not upload.done:
            self.step()
        if not upload.ok:
            raise RuntimeError(f'the emulated robot refused the gait: {upload.message}')
        stand_until = self.t + 1.0
        while self.t < stand_until:
            self.step()
        self.odometry = TrialOdometry()
        for sample in self.history:
            self.odometry.add(*sample)
        x0, y0, yaw0 = self._pose()
        imu_start = self.odometry.newest_time()
        walks = len(self.fw.trials)
        start = self.link.start_trial(settle + duration, upload.result['gait_id'])
        done_at = walk_start = settled = None
        while done_at is None or not self.odometry.window_closes(
            self.t - done_at, REST_MIN, REST_MAX
        ):
            self.step()
            if walk_start is None and len(self.fw.trials) > walks:
                walk_start = self.t
            if settled is None and walk_start is not None and self.t >= walk_start + settle:
                settled = self.sim.base_pose()[0][:2].copy()
            if done_at is None and start.done and self.link.trial_state.name == 'DONE':
                done_at = self.t
        x1, y1, yaw1 = self._pose()
        record = self.fw.trials[-1]
        true_speed = record.summary()['speed']
        if settle > 0:
            heading = record.start_yaw + record.crab_angle
            d = record.end_position[:2] - settled
            true_speed = float(d[0] * math.cos(heading) + d[1] * math.sin(heading)) / duration
        timed = self.odometry.timed_part(imu_start, settle, duration)
        est = self.odometry.estimate(gait.crab_angle, duration, timed)
        ex, ey = self.odometry.in_start_frame(est.displacement)
        self.odometry = None
        c, s = math.cos(yaw0), math.sin(yaw0)
        true_move = (
            c * (x1 - x0) + s * (y1 - y0),
            -s * (x1 - x0) + c * (y1 - y0),
            math.pi - (math.pi - (yaw1 - yaw0)) % (2.0 * math.pi),
        )
        return MeasuredTrial(true_speed, est.speed, true_move, (ex, ey, est.yaw_change))

    def trial(self, gait) -> tuple[float, float]:
        """Walk one 5 s trial of ``gait``: (the emulator's true speed, the IMU estimate) [m/s]."""
        m = self.measure(gait, 5.0)
        return m.true_speed, m.estimated_speed


@dataclass(frozen=True)
class DeadReckoning:
    """How far dead reckoning from the bridge's trial odometry drifts from the truth."""

    step_errors: tuple[float, ...]  # m: |estimated - true| displacement of each trial
    yaw_errors: tuple[float, ...]  # rad: estimated - true heading change of each trial
    drift: tuple[float, ...]  # m: |dead-reckoned - true position| after 1, 2, ... trials


def dead_reckoning(sim: Simulator, gaits, duration: float, seed: int) -> DeadReckoning:
    """Walk ``gaits`` one after another on an emulated robot; compose both poses; compare."""
    robot = ConsecutiveTrials(sim, seed)
    true_pose, est_pose = ChainedPose(), ChainedPose()  # est_pose: what bridge_node's odom says
    steps, yaws, drift = [], [], []
    for gait in gaits:
        m = robot.measure(gait, duration)
        steps.append(
            math.hypot(m.estimated_move[0] - m.true_move[0], m.estimated_move[1] - m.true_move[1])
        )
        yaws.append(m.estimated_move[2] - m.true_move[2])
        true_pose.add(*m.true_move, duration)
        est_pose.add(*m.estimated_move, duration)
        drift.append(math.hypot(est_pose.x - true_pose.x, est_pose.y - true_pose.y))
    return DeadReckoning(tuple(steps), tuple(yaws), tuple(drift))
