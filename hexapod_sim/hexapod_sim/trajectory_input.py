# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Turn an incoming joint trajectory into the simulator's control table.

One gait cycle, any joint order; clear errors for anything malformed. ROS-free: takes plain arrays.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np


class TrajectoryError(ValueError):
    """The trajectory cannot be played; the message says why."""


#: Bounds of an accepted gait cycle: the controller's longest period is 10 s (table 4.1), sent
#: at up to 1 kHz. Larger requests are refused before anything is allocated for them.
MAX_CYCLE_SECONDS = 60.0
MAX_POINTS = 60_000


@dataclass(frozen=True)
class CycleTable:
    """One gait cycle at the simulator's step: positions, velocities (N, 18), period."""

    positions: np.ndarray  # (N, 18) URDF joint order, at the simulator's time step
    velocities: np.ndarray  # (N, 18)
    period: float  # s


def _check_names(names: list[str], expected: list[str]) -> None:
    """Refuse joint names that are not the robot's joints, each once."""
    if len(set(names)) != len(names):
        raise TrajectoryError('duplicate joint names in the trajectory')
    if set(names) != set(expected):
        missing = sorted(set(expected) - set(names))
        unknown = sorted(set(names) - set(expected))
        raise TrajectoryError(
            f"joint names must be the robot's {len(expected)} joints; "
            f'missing {missing}, unknown {unknown}'
        )


def _point_arrays(
    n_joints: int, times: Sequence[float], positions, velocities
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Return (times, positions, velocities or None) as arrays, refusing wrong shapes."""
    n = len(times)
    if n < 2:
        raise TrajectoryError(f'a gait cycle needs at least 2 points, got {n}')
    if n > MAX_POINTS:
        raise TrajectoryError(f'a gait cycle may have at most {MAX_POINTS} points, got {n}')
    if len(positions) != n or (len(velocities) and len(velocities) != n):
        raise TrajectoryError('positions (and velocities, if given) need one entry per point')
    try:
        q = np.asarray(positions, dtype=float)
    except ValueError:
        raise TrajectoryError('every point needs one position per joint') from None
    if q.shape != (n, n_joints):
        raise TrajectoryError(f'every point needs {n_joints} positions')
    if not np.isfinite(q).all():
        raise TrajectoryError('positions must be finite')
    v = None
    if len(velocities) and any(len(v) for v in velocities):
        try:
            v = np.asarray(velocities, dtype=float)
        except ValueError:
            raise TrajectoryError('every point needs 0 or one velocity per joint') from None
        if v.shape != q.shape or not np.isfinite(v).all():
            raise TrajectoryError(
                'velocities must be finite, one per joint for every point (or none)'
            )
    return np.asarray(times, dtype=float), q, v


def _sample_step(t: np.ndarray) -> float:
    """Return the points' uniform spacing [s], refusing times that are not one sampled cycle."""
    spacing = np.diff(t)
    if not np.isfinite(t).all() or t[0] != 0.0 or np.any(spacing <= 0):
        raise TrajectoryError('time_from_start must start at 0 and increase strictly')
    if t[-1] + spacing.mean() > MAX_CYCLE_SECONDS:
        raise TrajectoryError(
            f'a gait cycle may last at most {MAX_CYCLE_SECONDS:g} s, got '
            f'{t[-1] + spacing.mean():.6g} s'
        )
    step = float(spacing.mean())
    if np.abs(spacing - step).max() > 1e-6:
        raise TrajectoryError('points must be uniformly spaced in time (one sampled gait cycle)')
    return step


def cycle_from_points(
    joint_names: Sequence[str],
    times: Sequence[float],
    positions: Sequence[Sequence[float]],
    velocities: Sequence[Sequence[float]],
    urdf_joint_names: Sequence[str],
    dt: float,
) -> CycleTable:
    """
    Validate one cycle of a trajectory and resample it onto the simulator's step ``dt``.

    The cycle repeats with period = last time + sample spacing (samples are uniform, as
    gait_node publishes them). Samples already at ``dt`` are used exactly as given; other rates
    are interpolated linearly (cyclically). Missing velocities are taken as finite differences.
    """
    names, expected = list(joint_names), list(urdf_joint_names)
    _check_names(names, expected)
    t, q, v = _point_arrays(len(names), times, positions, velocities)
    step = _sample_step(t)
    period = t[-1] + step
    order = [names.index(name) for name in expected]
    q = q[:, order]
    if v is not None:
        v = v[:, order]
    else:
        v = (np.roll(q, -1, axis=0) - np.roll(q, 1, axis=0)) / (2.0 * step)
    if abs(step - dt) <= 1e-9:
        return CycleTable(q, v, period)
    steps = max(2, int(round(period / dt)))
    grid = np.arange(steps) * (period / steps)
    tt = np.concatenate([t, [period]])
    qq = np.vstack([q, q[:1]])
    vv = np.vstack([v, v[:1]])
    resampled_q = np.column_stack([np.interp(grid, tt, qq[:, j]) for j in range(q.shape[1])])
    resampled_v = np.column_stack([np.interp(grid, tt, vv[:, j]) for j in range(q.shape[1])])
    return CycleTable(resampled_q, resampled_v, period)
