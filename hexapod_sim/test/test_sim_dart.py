# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The DART engine, the judge: its control tripod against the thesis, its settings, its limits."""

from hexapod_gait import preset
from hexapod_sim import create_simulator, evaluate_gait, SimConfig
from hexapod_sim.engine_settings import DartSettings
from hexapod_sim.simulator import JUDGE_ENGINE
import numpy as np
import pytest

#: The thesis's simulated control tripod, intact (S0) [m/s].
THESIS_S0 = 0.283


@pytest.fixture(scope='module')
def dart():
    with create_simulator(SimConfig(engine='dart')) as sim:
        yield sim


def test_dart_is_the_judge():
    assert JUDGE_ENGINE == 'dart'


def test_the_intact_control_tripod_walks_within_20_percent_of_the_thesis(dart):
    result = evaluate_gait(preset('control'), dart, collisions_fatal=False, failed_legs=())
    assert result.valid, result.reason
    assert abs(result.speed - THESIS_S0) <= 0.2 * THESIS_S0, result.speed
    # a walk, not a run: every foot is on the ground most of the time
    assert (result.descriptor > 0.4).all(), result.descriptor


def test_a_lifted_leg_slows_the_control_tripod_and_two_stop_it_more(dart):
    intact = evaluate_gait(preset('control'), dart, collisions_fatal=False, failed_legs=()).speed
    one = evaluate_gait(preset('control'), dart, collisions_fatal=False, failed_legs=(1,)).speed
    two = evaluate_gait(preset('control'), dart, collisions_fatal=False, failed_legs=(1, 2))
    assert one < 0.7 * intact
    assert two.speed < one
    assert two.collision_steps >= 0


def test_a_fresh_and_a_reused_simulator_give_the_same_walk(dart):
    first = evaluate_gait(preset('tripod'), dart, collisions_fatal=False, failed_legs=(3,))
    evaluate_gait(preset('wave'), dart, collisions_fatal=False, failed_legs=())
    again = evaluate_gait(preset('tripod'), dart, collisions_fatal=False, failed_legs=(3,))
    with create_simulator(SimConfig(engine='dart')) as fresh:
        new = evaluate_gait(preset('tripod'), fresh, collisions_fatal=False, failed_legs=(3,))
    assert again.fitness == first.fitness == new.fitness
    np.testing.assert_array_equal(again.descriptor, new.descriptor)


def test_the_servo_saturates_at_the_urdf_effort(dart):
    dart.set_failed_legs(())
    q0 = np.zeros(18)
    dart.reset(q0)
    target = q0.copy()
    target[1] = 2.0  # a femur far from where it stands
    dart.command(target, np.zeros(18))
    dart.step()
    _, _, torque = dart.joint_states()
    femur_effort = dart.model.limits[1].effort
    assert torque[1] == pytest.approx(femur_effort)


@pytest.mark.parametrize(
    'settings',
    [
        {'substeps': 0},
        {'substeps': 1.5},
        {'collision_detector': 'dart'},
        {'time_step': 0.1},
        {'compliance_slope': float('nan')},
    ],
)
def test_bad_settings_are_refused_with_the_setting_named(settings):
    name = next(iter(settings))
    with pytest.raises(ValueError, match=name):
        DartSettings(**settings)


def test_dart_does_not_render_and_says_which_engines_do(dart):
    with pytest.raises(RuntimeError, match='pybullet'):
        dart.render()
