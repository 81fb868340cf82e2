# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""IK/FK/joint-velocity equations (thesis 3.38-3.50)."""

from __future__ import annotations

from hexapod_gait import build_joint_table, default_kinematics, preset
from hexapod_gait.parameters import GaitParameters
import numpy as np
import pytest


def random_reachable_points(n: int, seed: int) -> np.ndarray:
    """
    Foot points from FK of random knee-down joint angles.

    Kept where the foot is outboard of the femur joint (the workspace eq. 3.38's branch
    covers).
    """
    kin = default_kinematics()
    rng = np.random.default_rng(seed)
    angles = np.column_stack(
        [rng.uniform(-1.7, 1.7, n), rng.uniform(-1.4, 1.4, n), rng.uniform(-2.9, -0.05, n)]
    )
    outboard = kin.a2 * np.cos(angles[:, 1]) + kin.a3 * np.cos(angles[:, 1] + angles[:, 2]) > 1e-3
    return kin.forward(angles[outboard])


def test_link_lengths_come_from_the_urdf():
    kin = default_kinematics()
    assert (kin.a1, kin.a2, kin.a3) == pytest.approx((0.05317, 0.1019, 0.1474))


def test_ik_then_fk_returns_the_commanded_points():
    kin = default_kinematics()
    points = random_reachable_points(5000, seed=3)
    assert len(points) > 2000
    err = kin.reach_error(points, kin.inverse(points))
    assert err.max() <= 1e-9


def test_unreachable_point_has_a_large_reach_error():
    kin = default_kinematics()
    far = np.array([[0.5, 0.0, -0.1]])
    assert kin.reach_error(far, kin.inverse(far))[0] > 0.1


def test_joint_velocities_match_finite_differences_inside_each_phase():
    rate = 4800.0
    for gait in [
        preset('tripod'),
        preset('wave'),
        GaitParameters(
            body_velocity=0.2,
            body_height=0.12,
            radius=[0.12, 0.14, 0.16, 0.18, 0.15, 0.13],
            angle_offset=[0.3, -0.2, 0.0, 0.1, -0.4, 0.2],
            step_height=[0.05, 0.07, 0.04, 0.06, 0.08, 0.05],
            duty_factor=[0.55, 0.6, 0.5, 0.7, 0.65, 0.6],
            phase_offset=[0.0, 0.5, 0.1, 0.6, 0.2, 0.7],
        ),
    ]:
        table = build_joint_table(gait, rate=rate)
        fd = (table.positions[2:] - table.positions[:-2]) * rate / 2.0
        analytic = table.velocities[1:-1]
        # exclude samples next to a support/swing switch (velocity is discontinuous there)
        stance = table.stance
        switch = np.zeros(len(table), dtype=bool)
        for leg in range(6):
            change = np.flatnonzero(stance[:, leg] != np.roll(stance[:, leg], 1))
            for c in change:
                switch[np.arange(c - 3, c + 3) % len(table)] = True
        ok = ~switch[1:-1]
        scale = np.abs(analytic[ok]).max()
        assert np.abs(fd[ok] - analytic[ok]).max() <= 1e-3 * scale
