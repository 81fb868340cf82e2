# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Omnidirectional gaits: any crab angle, the turn rate, and the omni genotype (IK/FK checks)."""

from __future__ import annotations

import math

from hexapod_gait import build_joint_table, default_kinematics, preset, ReachabilityError
from hexapod_gait.parameters import (
    from_omni_genotype,
    GaitParameterError,
    genotype_mapping,
    OMNI_GENOTYPE_SIZE,
    to_genotype,
    to_omni_genotype,
)
from hexapod_gait.trajectory import default_geometry, key_points
import numpy as np
import pytest

RATE = 240.0


def feet_in_base(gait) -> tuple[np.ndarray, np.ndarray]:
    """Foot positions (N, 6, 2) in base_link from FK of the joint table, and stance (N, 6)."""
    table = build_joint_table(gait, rate=RATE)
    geo = default_geometry()
    q = table.positions.reshape(-1, 6, 3)
    feet = default_kinematics().forward(q)[..., :2]  # leg frames
    c, s = np.cos(geo.yaw), np.sin(geo.yaw)
    x = geo.mount_xy[:, 0] + c * feet[..., 0] - s * feet[..., 1]
    y = geo.mount_xy[:, 1] + s * feet[..., 0] + c * feet[..., 1]
    return np.stack([x, y], axis=-1), table.stance


def stance_velocities(gait) -> tuple[np.ndarray, np.ndarray]:
    """Each leg's foot velocity in base_link (6, 2) mid-stance, and the foot positions there."""
    feet, stance = feet_in_base(gait)
    vel, pos = np.zeros((6, 2)), np.zeros((6, 2))
    for leg in range(6):
        rows = np.flatnonzero(stance[:, leg])
        # consecutive stance rows (the stance may wrap around the cycle's end)
        k = next(int(r) for r in rows if r + 1 in set(rows.tolist()))
        vel[leg] = (feet[k + 1, leg] - feet[k, leg]) * RATE
        pos[leg] = feet[k, leg]
    return vel, pos


@pytest.mark.parametrize('crab', [0.0, math.pi / 2, 2.5, -math.pi, -1.0])
def test_every_stance_foot_moves_against_the_crab_direction(crab):
    gait = preset('tripod').replace(crab_angle=crab)
    vel, _ = stance_velocities(gait)
    expected = -gait.body_velocity * np.array([math.cos(crab), math.sin(crab)])
    np.testing.assert_allclose(vel, np.tile(expected, (6, 1)), atol=2e-3)


def test_a_turn_in_place_moves_each_stance_foot_around_the_body_centre():
    gait = preset('tripod').replace(body_velocity=0.0, turn_rate=0.4)
    vel, pos = stance_velocities(gait)
    # the chord of the arc: the velocity -omega z x c of the foot-path centre c, constant in stance
    start, _, end = key_points(gait)
    geo = default_geometry()
    centre_leg = 0.5 * (start + end)[:, :2]
    c, s = np.cos(geo.yaw), np.sin(geo.yaw)
    centre = np.stack(
        [
            geo.mount_xy[:, 0] + c * centre_leg[:, 0] - s * centre_leg[:, 1],
            geo.mount_xy[:, 1] + s * centre_leg[:, 0] + c * centre_leg[:, 1],
        ],
        axis=1,
    )
    expected = -0.4 * np.stack([-centre[:, 1], centre[:, 0]], axis=1)
    np.testing.assert_allclose(vel, expected, atol=2e-3)
    # tangential: no foot moves towards or away from the body centre
    assert np.abs(np.sum(vel * centre, axis=1)).max() < 1e-3
    # and the feet turn the body counter-clockwise (z x c points that way for positive omega)
    assert np.all(centre[:, 0] * vel[:, 1] - centre[:, 1] * vel[:, 0] < 0)


def test_no_turn_is_the_thesis_stride():
    gait = preset('tripod')
    start, _, end = key_points(gait)
    stride = np.linalg.norm((start - end)[:, :2], axis=1)
    np.testing.assert_allclose(stride, gait.body_velocity * gait.period * gait.duty_factor)
    with_zero = key_points(gait.replace(turn_rate=0.0))
    for a, b in zip((start, _, end), with_zero):
        np.testing.assert_array_equal(a, b)


def test_a_turn_too_fast_for_the_legs_is_unreachable_and_named():
    gait = preset('tripod').replace(
        turn_rate=1.0, body_velocity=0.5, duty_factor=[0.95] * 6, radius=[0.28] * 6
    )
    with pytest.raises(ReachabilityError, match='leg'):
        build_joint_table(gait)


def test_turn_rate_is_range_checked_by_name():
    with pytest.raises(GaitParameterError, match=r'turn_rate.*\[-1, 1\] rad/s'):
        preset('tripod').replace(turn_rate=1.5)
    with pytest.raises(GaitParameterError, match='turn_rate'):
        preset('tripod').replace(turn_rate=float('nan'))


def test_omni_genotype_round_trips_and_names_its_mapping():
    rng = np.random.default_rng(3)
    for _ in range(20):
        genes = rng.random(OMNI_GENOTYPE_SIZE)
        gait = from_omni_genotype(genes)
        np.testing.assert_allclose(to_omni_genotype(gait), genes, atol=1e-12)
    mapping = genotype_mapping('omni/v1')
    assert mapping.size == 34 and mapping.decode is from_omni_genotype
    with pytest.raises(ValueError, match='unknown genotype mapping'):
        genotype_mapping('omni/v9')
    with pytest.raises(GaitParameterError, match='expected 34 genes'):
        from_omni_genotype(np.zeros(32))


def test_a_turning_gait_has_no_thesis_genotype():
    with pytest.raises(GaitParameterError, match='no turn'):
        to_genotype(preset('tripod').replace(turn_rate=0.1))
    assert to_genotype(preset('tripod')).shape == (32,)
