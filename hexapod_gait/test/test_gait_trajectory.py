# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Foot trajectories, stance timing, key points, phase offsets, presets, reachability."""

from __future__ import annotations

from hexapod_gait import (
    build_joint_table,
    foot_trajectory,
    GaitParameters,
    key_points,
    preset,
    PRESETS,
    ReachabilityError,
    stance_mask,
)
from hexapod_gait.footfall import plot_footfall, swing_groups
from hexapod_gait.trajectory import ROBOT_RATE, SIM_RATE
import numpy as np
import pytest


def gait(**changes) -> GaitParameters:
    return preset('tripod').replace(**changes)


@pytest.mark.parametrize('duty', [0.2, 1 / 3, 0.5, 0.6, 2 / 3, 0.75, 5 / 6, 0.9])
@pytest.mark.parametrize('rate', [SIM_RATE, ROBOT_RATE])
def test_each_leg_is_in_stance_for_duty_factor_times_period(duty, rate):
    g = gait(
        duty_factor=[duty] * 6,
        phase_offset=[0.0, 0.13, 0.5, 0.77, 1 / 3, 5 / 6],
        body_velocity=0.1,
    )
    table = build_joint_table(g, rate=rate)
    expected = duty * g.period * rate
    assert np.all(np.abs(table.stance.sum(axis=0) - expected) <= 1.0)
    assert np.all(table.stance.sum(axis=0) == np.round(expected)) or duty * rate % 1 != 0


def test_trajectory_passes_through_the_key_points():
    g = gait(
        phase_offset=[0.0, 0.25, 0.1, 0.6, 0.35, 0.9],
        duty_factor=[0.5, 0.6, 0.7, 0.55, 0.65, 0.75],
        body_velocity=0.15,
    )
    start, mid, end = key_points(g)
    beta, psi, period = g.duty_factor, g.phase_offset, g.period
    for leg in range(6):
        t0 = psi[leg] * period  # leg's cycle starts: p_start
        t_end = t0 + beta[leg] * period  # support ends: p_end
        t_mid = t_end + 0.5 * (1 - beta[leg]) * period  # half-way through swing: p_mid
        pos, _, _ = foot_trajectory(g, np.array([t0, t_end, t_mid, t0 + period]))
        np.testing.assert_allclose(pos[leg, 0], start[leg], atol=1e-12)
        np.testing.assert_allclose(pos[leg, 1], end[leg], atol=1e-12)
        np.testing.assert_allclose(pos[leg, 2], mid[leg], atol=1e-12)
        np.testing.assert_allclose(pos[leg, 3], start[leg], atol=1e-12)  # periodic


def test_support_is_a_straight_line_at_constant_velocity_matching_body_speed():
    g = gait(body_velocity=0.25)
    times = np.arange(240) / 240
    pos, vel, stance = foot_trajectory(g, times)
    for leg in range(6):
        v = vel[leg][stance[leg]]
        np.testing.assert_allclose(v, np.broadcast_to(v[0], v.shape), atol=1e-12)
        assert np.linalg.norm(v[0][:2]) == pytest.approx(0.25)  # foot moves at body speed
        # flat on the ground
        assert np.all(pos[leg][stance[leg]][:, 2] == pos[leg][stance[leg]][0, 2])
    # swing lifts the foot to exactly the step height above the ground
    assert pos[:, :, 2].max(axis=1) - pos[:, :, 2].min(axis=1) == pytest.approx(
        g.step_height, abs=1e-6
    )


def test_phase_offset_shifts_a_leg_in_time():
    base = gait(phase_offset=[0.0] * 6)
    shifted = gait(phase_offset=[0.0, 0.25, 0.0, 0.0, 0.0, 0.0])
    times = np.arange(240) / 240
    a, _, _ = foot_trajectory(base, times)
    b, _, _ = foot_trajectory(shifted, times)
    np.testing.assert_allclose(np.roll(a[1], 60, axis=0), b[1], atol=1e-12)
    np.testing.assert_allclose(a[0], b[0], atol=0)


def _groups(name: str) -> list[set[int]]:
    g = preset(name)
    return [set(s) for s in swing_groups(stance_mask(g, np.arange(720) / 240))]


def test_tripod_alternates_135_and_246():
    assert sorted(map(sorted, _groups('tripod'))) == [[1, 3, 5], [2, 4, 6]]
    pattern = stance_mask(preset('tripod'), np.arange(240) / 240)
    assert np.all(pattern[:, [0, 2, 4]] == pattern[:, [0]]) and np.all(
        pattern[:, [1, 3, 5]] == ~pattern[:, [0]]
    )


def test_wave_swings_one_leg_at_a_time():
    groups = _groups('wave')
    assert all(len(g) == 1 for g in groups) and len(groups) == 6
    assert stance_mask(preset('wave'), np.arange(240) / 240).sum(axis=1).min() == 5


def test_quadruped_swings_two_at_a_time():
    groups = _groups('quadruped')
    assert sorted(map(sorted, groups)) == [[1, 4], [2, 5], [3, 6]]


def test_control_gait_is_the_thesis_tripod():
    c = preset('control')
    assert (c.body_velocity, c.body_height) == (0.3, 0.14)
    assert np.all(c.duty_factor == 0.5)
    with pytest.raises(ValueError, match='known: tripod'):
        preset('gallop')


def test_all_presets_are_reachable_at_both_rates():
    for name in PRESETS:
        for rate in (SIM_RATE, ROBOT_RATE):
            table = build_joint_table(preset(name), rate=rate)
            assert table.positions.shape == (int(rate), 18)
            assert np.isfinite(table.velocities).all()


def test_unreachable_gait_names_leg_and_time():
    far = gait(radius=[0.15, 0.15, 0.29, 0.15, 0.15, 0.15])
    with pytest.raises(ReachabilityError) as info:
        build_joint_table(far)
    assert info.value.leg == 3
    assert 0.0 <= info.value.time < 1.0
    assert 'leg 3' in str(info.value) and 't = ' in str(info.value)


def test_rate_must_divide_the_period():
    with pytest.raises(ValueError, match='whole number'):
        build_joint_table(preset('tripod'), rate=100.5)


def test_footfall_png(tmp_path):
    g = preset('tripod')
    times = np.arange(720) / 240
    out = plot_footfall(stance_mask(g, times), times, tmp_path / 'ff.png', title='tripod')
    data = out.read_bytes()
    assert data[:8] == b'\x89PNG\r\n\x1a\n' and len(data) > 5000
    with pytest.raises(ValueError):
        plot_footfall(np.zeros((10, 5), bool), np.arange(10), tmp_path / 'x.png')
