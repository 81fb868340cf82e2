# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Trial odometry from an IMU: speed along the walking direction over one trial.

The robot stands still before a trial starts and after its walk stops. Between those two
rests, horizontal acceleration (accelerometer specific force rotated to the world with the
IMU's Euler angles, gravity removed) is integrated to velocity; the velocity that remains at
the final rest is drift (accelerometer bias, tilt error leaking gravity), and is removed as a
linear ramp over the window (a zero-velocity update at both ends), then velocity is integrated
to displacement. A settled trial walks a while untimed before its timed part: the rests still
bound the window, and the speed is the displacement over the timed part only (``timed``).
The accuracy this achieves is measured against ground truth in
hexapod_bridge/test/test_bridge_odometry.py and stated in docs/bridge.md.
"""

from __future__ import annotations

from dataclasses import dataclass
import math

import numpy as np

GRAVITY = 9.81

#: Accuracy of the trial-speed estimate [m/s] (odometry covariances, docs/bridge.md), measured
#: against the emulator's ground truth with Xsens-like noise in test_bridge_odometry.py, the
#: window closing once the body is at rest (window_closes): over 20 trials walked one after
#: another (no reset; they tilt and turn hard) of today's default map's fastest gaits on MuJoCo
#: the worst error was 0.186 m/s (RMS 0.052), of the first default map's fastest gaits on
#: PyBullet 0.079 (RMS 0.024). Steady gaits (the presets, random reachable gaits walked from
#: rest) stay within STEADY_GAIT_ACCURACY (worst 0.018 m/s).
SPEED_ACCURACY = 0.19

#: The body is at rest once its horizontal acceleration (world frame, gravity removed) has varied
#: by less than REST_ACCEL_STD [m/s^2] (RMS about its mean, so a constant bias does not count)
#: over the last REST_WINDOW s. Measured 0.5 s after a walk on the emulator: 0.05-0.08 standing
#: still with Xsens-like noise, 0.1-0.7 after steady gaits, 1.5-6 after the new default map's
#: fastest gaits (docs/bridge.md).
REST_WINDOW = 0.25
REST_ACCEL_STD = 1.0
STEADY_GAIT_ACCURACY = 0.025


def rotation_from_euler_deg(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """Sensor-to-world rotation for Xsens Euler angles (Z-Y-X: yaw, then pitch, then roll)."""
    r, p, y = (math.radians(v) for v in (roll, pitch, yaw))
    cr, sr, cp, sp, cy, sy = (
        math.cos(r),
        math.sin(r),
        math.cos(p),
        math.sin(p),
        math.cos(y),
        math.sin(y),
    )
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


@dataclass(frozen=True)
class TrialEstimate:
    """The IMU estimate of one trial's displacement and speed along the walking direction."""

    distance: float  # m along the walking direction, over the timed part
    speed: float  # m/s = distance / timed duration
    displacement: np.ndarray  # (2,) world x, y [m] over the window (the whole walk)
    samples: int
    drift_velocity: float  # |velocity| removed by the end-of-window zero-velocity update [m/s]
    yaw_change: float = 0.0  # heading at the window's end minus at its start [rad], (-pi, pi]
    timed_displacement: np.ndarray | None = None  # (2,) world x, y [m] over the timed part

    @property
    def timed(self) -> np.ndarray:
        """World x, y [m] walked in the timed part (the whole window if it is all timed)."""
        return self.displacement if self.timed_displacement is None else self.timed_displacement


class TrialOdometry:
    """Collect IMU samples for one trial window and estimate the distance walked."""

    def __init__(self) -> None:
        self.times: list[float] = []
        self.accel_world: list[np.ndarray] = []
        self.yaw0: float | None = None
        self.yaw: float | None = None  # the latest heading [rad]

    def add(
        self,
        t: float,
        acc_sensor: tuple[float, float, float],
        euler_deg: tuple[float, float, float],
    ) -> None:
        """
        One IMU sample at time t [s] (the IMU's clock, e.g. its sample counter / rate).

        acc_sensor is the mean specific force over the interval ending at t.
        """
        rot = rotation_from_euler_deg(*euler_deg)
        if self.yaw0 is None:
            self.yaw0 = math.radians(euler_deg[2])
        self.yaw = math.radians(euler_deg[2])
        a = rot @ np.asarray(acc_sensor, dtype=float)
        a[2] -= GRAVITY
        self.times.append(float(t))
        self.accel_world.append(a)

    def newest_time(self) -> float | None:
        """Return the IMU clock of the newest sample (None before the first)."""
        return self.times[-1] if self.times else None

    def timed_part(
        self, start: float | None, settle: float, duration: float
    ) -> tuple[float, float] | None:
        """
        Return the timed part of a settled trial on the IMU's clock, for :meth:`estimate`.

        ``start``: the IMU clock when the start was sent (None: the window's first sample).
        None when nothing settles (``settle`` 0): the whole window is the walk.
        """
        if settle <= 0 or not self.times:
            return None
        begin = self.times[0] if start is None else start
        return begin + settle, begin + settle + duration

    def in_start_frame(self, displacement: np.ndarray) -> tuple[float, float]:
        """Return a world displacement (x, y) in the frame the robot started the window in."""
        yaw0 = self.yaw0 or 0.0
        c, s = math.cos(yaw0), math.sin(yaw0)
        dx, dy = (float(v) for v in displacement)
        return c * dx + s * dy, -s * dx + c * dy

    def at_rest(self) -> bool:
        """Return whether the last REST_WINDOW s of samples say the body is still (see above)."""
        if len(self.times) < 3:
            return False
        t = np.asarray(self.times)
        recent = np.asarray(self.accel_world)[t >= t[-1] - REST_WINDOW, :2]
        spread = np.sqrt(np.mean(np.sum(np.square(recent - recent.mean(axis=0)), axis=1)))
        return len(recent) >= 3 and bool(spread < REST_ACCEL_STD)

    def window_closes(self, since_done: float, rest_min: float, rest_max: float) -> bool:
        """
        Return whether the window may close ``since_done`` s after the walk was reported done.

        After at least ``rest_min`` s, once the body is at rest (:meth:`at_rest`); after
        ``rest_max`` s in any case. A body still moving where the estimate assumes rest skews it.
        """
        return since_done >= rest_max or (since_done >= rest_min and self.at_rest())

    def position_so_far(self) -> np.ndarray:
        """Plain double integration up to now (no drift correction): the live estimate."""
        if len(self.times) < 2:
            return np.zeros(2)
        t, v = self._velocity()
        return np.sum(0.5 * (v[1:] + v[:-1]) * np.diff(t)[:, None], axis=0)

    def _velocity(self) -> tuple[np.ndarray, np.ndarray]:
        """
        Velocity at each sample time.

        Samples are interval means, so the rectangle rule over each interval is exact for them.
        """
        t = np.asarray(self.times)
        a = np.asarray(self.accel_world)[:, :2]
        v = np.concatenate([[np.zeros(2)], np.cumsum(a[1:] * np.diff(t)[:, None], axis=0)])
        return t, v

    def estimate(
        self,
        crab_angle: float,
        walk_duration: float,
        timed: tuple[float, float] | None = None,
    ) -> TrialEstimate:
        """
        Distance along the walking direction, assuming rest at both ends of the window.

        The walking direction is the crab angle relative to the heading at the window's start.
        ``timed`` (start, end) on the IMU's clock: the part of the walk that is timed (a settled
        trial); its length is ``walk_duration``. None: the whole window is the walk.
        """
        if len(self.times) < 10:
            raise ValueError(f'too few IMU samples for a trial estimate ({len(self.times)})')
        t, v = self._velocity()
        dt = np.diff(t)
        drift = v[-1].copy()
        v -= np.outer((t - t[0]) / (t[-1] - t[0]), drift)
        # position at every sample, in the world frame, from the window's start
        position = np.vstack([np.zeros(2), np.cumsum(0.5 * (v[1:] + v[:-1]) * dt[:, None], 0)])
        displacement = position[-1]
        part = None
        if timed is not None:
            start, end = timed
            if not (t[0] <= start < end <= t[-1]):
                raise ValueError(
                    f'the timed part {start:.2f}-{end:.2f} s is not inside the IMU window'
                    f' {t[0]:.2f}-{t[-1]:.2f} s (IMU clock)'
                )
            part = np.array([np.interp(end, t, position[:, k]) for k in (0, 1)]) - np.array(
                [np.interp(start, t, position[:, k]) for k in (0, 1)]
            )
        heading = (self.yaw0 or 0.0) + crab_angle
        walked = displacement if part is None else part
        distance = float(walked[0] * math.cos(heading) + walked[1] * math.sin(heading))
        turned = (self.yaw or 0.0) - (self.yaw0 or 0.0)
        return TrialEstimate(
            distance,
            distance / walk_duration,
            displacement,
            len(t),
            float(np.linalg.norm(drift)),
            math.pi - (math.pi - turned) % (2.0 * math.pi),
            part,
        )


@dataclass
class ChainedPose:
    """
    The robot's pose in ``odom`` (REP 105: continuous), trial after trial.

    Each trial's displacement, given in the frame the robot started that trial in, is composed
    onto the pose it started from. Nothing is measured between trials (the robot stands), so
    the pose changes at a trial's end only; ``variance`` (of x and of y) adds each trial's
    stated accuracy over its walk.
    """

    x: float = 0.0  # [m]
    y: float = 0.0
    yaw: float = 0.0  # [rad], in (-pi, pi]
    variance: float = 0.0  # [m^2]
    trials: int = 0

    def add(self, dx: float, dy: float, dyaw: float, walked: float) -> None:
        """Compose one trial: (dx, dy) [m] in its start frame, dyaw [rad], ``walked`` [s]."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        self.x, self.y = self.x + c * dx - s * dy, self.y + s * dx + c * dy
        self.yaw = math.atan2(math.sin(self.yaw + dyaw), math.cos(self.yaw + dyaw))
        self.variance += (SPEED_ACCURACY * walked) ** 2
        self.trials += 1
