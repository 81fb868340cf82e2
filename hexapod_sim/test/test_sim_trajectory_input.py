# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Incoming joint trajectories: validation and resampling onto the simulator step."""

from __future__ import annotations

from hexapod_description import load_model
from hexapod_gait import build_joint_table, preset
from hexapod_sim.simulator import body_height_from_joints
from hexapod_sim.trajectory_input import cycle_from_points, TrajectoryError
import numpy as np
import pytest

NAMES = list(load_model().joint_names)
DT = 1.0 / 240.0


def _args(table, names=NAMES):
    times = (np.arange(len(table.positions)) / table.rate).tolist()
    return names, times, table.positions.tolist(), table.velocities.tolist(), NAMES, DT


def test_sim_rate_table_is_used_exactly_and_joint_order_is_restored():
    table = build_joint_table(preset('tripod'))
    cycle = cycle_from_points(*_args(table))
    assert np.array_equal(cycle.positions, table.positions) and cycle.period == pytest.approx(1.0)
    perm = np.random.default_rng(0).permutation(18)
    shuffled = cycle_from_points(
        [NAMES[i] for i in perm],
        _args(table)[1],
        table.positions[:, perm].tolist(),
        table.velocities[:, perm].tolist(),
        NAMES,
        DT,
    )
    assert np.array_equal(shuffled.positions, table.positions)


def test_robot_rate_table_is_resampled_to_the_sim_step():
    table = build_joint_table(preset('wave'), rate=120.0)
    cycle = cycle_from_points(*_args(table))
    assert cycle.positions.shape == (240, 18)
    np.testing.assert_allclose(cycle.positions[::2], table.positions, atol=1e-12)


@pytest.mark.parametrize(
    'mutate,match',
    [
        (lambda a: (a[0][:-1], *a[1:]), "missing \\['joint_6_3'\\]"),
        (lambda a: (a[0][:-1] + ['joint_7_1'], *a[1:]), "unknown \\['joint_7_1'\\]"),
        (lambda a: (a[0][:-1] + [a[0][0]], *a[1:]), 'duplicate'),
        (lambda a: (a[0], [], [], [], *a[4:]), 'at least 2 points'),
        (lambda a: (a[0], a[1], [r[:17] for r in a[2]], *a[3:]), '18 positions'),
        (lambda a: (a[0], [t * t for t in a[1]], *a[2:]), 'uniformly spaced'),
        (lambda a: (a[0], [t + 0.1 for t in a[1]], *a[2:]), 'start at 0'),
        (lambda a: (a[0], a[1], [[float('nan')] * 18] + a[2][1:], *a[3:]), 'finite'),
    ],
)
def test_malformed_trajectories_are_refused(mutate, match):
    table = build_joint_table(preset('tripod'))
    with pytest.raises(TrajectoryError, match=match):
        cycle_from_points(*mutate(list(_args(table))))


def test_body_height_is_recovered_from_the_joint_angles():
    for name in ('tripod', 'wave', 'quadruped'):
        gait = preset(name).replace(body_height=0.12)
        q0 = build_joint_table(gait).positions[0]
        assert body_height_from_joints(q0) == pytest.approx(0.12, abs=1e-12)
