# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Physics variants (issue 66): drawn from a seed, in their ranges, applied as they say."""

from __future__ import annotations

from dataclasses import replace

from hexapod_gait import build_joint_table, preset
from hexapod_sim import create_simulator, evaluate_gait, SimConfig
from hexapod_sim.engine_settings import MujocoSettings
from hexapod_sim.simulator import JointRows, Simulator
from hexapod_sim.variants import draw_variants, RANGES, variant_config
import numpy as np
import pytest


def test_variants_are_drawn_from_their_seed_within_their_ranges():
    a, b = draw_variants(16, 3), draw_variants(16, 3)
    assert a == b and draw_variants(16, 4) != a
    for variant in a:
        for name, (low, high) in RANGES.items():
            assert low <= getattr(variant, name) <= high, name
    assert {v.latency_rows for v in a} <= {0, 1, 2, 3, 4}
    assert len({v.friction for v in a}) == 16  # drawn, not one value
    with pytest.raises(ValueError, match=r'variants must be an integer in \[1, 256\]'):
        draw_variants(0, 3)
    with pytest.raises(ValueError, match='pybullet has none'):
        variant_config(SimConfig('pybullet'), a[0])


@pytest.mark.parametrize(
    'field,value,match',
    [
        ('latency_rows', -1, r'latency_rows must be in \[0, 48\]'),
        ('latency_rows', 1.5, 'latency_rows must be an integer'),
        ('effort_scale', 0.0, r'effort_scale must be in \[0.1, 10\]'),
        ('tibia_mass_scale', float('nan'), 'tibia_mass_scale must be in'),
    ],
)
def test_variant_settings_out_of_range_are_refused(field, value, match):
    with pytest.raises(ValueError, match=match):
        MujocoSettings(**{field: value})


def test_a_variant_scales_masses_and_servos_and_changes_the_fingerprint():
    variant = replace(
        draw_variants(1, 0)[0], base_mass_scale=1.1, femur_mass_scale=0.95, effort_scale=0.8
    )
    base = SimConfig('mujoco')
    config = variant_config(base, variant)
    assert config.friction == variant.friction
    assert config.fingerprint()['settings_sha256'] != base.fingerprint()['settings_sha256']
    with create_simulator(base) as plain, create_simulator(config) as varied:
        m0, m1 = plain.link_masses(), varied.link_masses()
        assert m1['base_link'] == pytest.approx(1.1 * m0['base_link'])
        assert m1['link_2_2'] == pytest.approx(0.95 * m0['link_2_2'])
        np.testing.assert_allclose(varied.m.actuator_forcerange, 0.8 * plain.m.actuator_forcerange)


@pytest.mark.parametrize('substeps', [1, 2])
def test_a_late_command_is_played_alike_by_the_native_batch_and_the_per_step_loop(substeps):
    """Latency: the rollout's shifted controls and the per-step queue play the same steps."""
    settings = MujocoSettings(substeps=substeps, latency_rows=3)
    gait = preset('tripod')
    with create_simulator(SimConfig('mujoco', mujoco=settings)) as sim:
        t = build_joint_table(gait, rate=1.0 / sim.dt)
        table = JointRows(t.positions, t.velocities)
        fast = sim.rollout([table], 240, record_tilt=True)[0]
        slow = Simulator._play(sim, table, 240, False, False, record_tilt=True)
        np.testing.assert_array_equal(fast.final_position, slow.final_position)
        assert fast.peak_tilt == slow.peak_tilt
    with create_simulator(SimConfig('mujoco', mujoco=replace(settings, latency_rows=0))) as sim:
        prompt = sim.rollout([table], 240)[0]
    assert not np.array_equal(prompt.final_position, fast.final_position)
    # a late tripod still walks: the delay shifts it, it does not break it
    with create_simulator(SimConfig('mujoco', mujoco=settings)) as sim:
        walked = evaluate_gait(gait, sim)
    assert walked.valid and walked.speed > 0.2
