# Copyright 2026 Hexapod adaptation team
# All rights reserved.
#
# Permission is hereby granted, free of charge, to any person obtaining a copy
# of this software and associated documentation files (the "Software"), to deal
# in the Software without restriction, including without limitation the rights
# to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
# copies of the Software, and to permit persons to whom the Software is
# furnished to do so, subject to the following conditions:
#
# The above copyright notice and this permission notice shall be included in all
# copies or substantial portions of the Software.
#
# THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
# IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
# FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
# AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
# LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
# OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
# SOFTWARE.
"""The navigator without ROS: poses, goals, the learned correction, the planner, episodes."""

import math

from hexapod_adapt.archive import load_archive
from hexapod_adapt.maps import NAVIGATION_MAP, shipped_map
from hexapod_adapt.navigation import (
    CorrectionGP,
    goal_problem,
    NavigationConfig,
    Outcome,
    Pose2D,
    RepertoirePolicy,
    run_episode,
    SimBody,
    SteeredTripod,
)
from hexapod_adapt.repertoire import Repertoire
from hexapod_sim import create_simulator, SimConfig
import numpy as np
import pytest

REPERTOIRE = shipped_map(NAVIGATION_MAP)


@pytest.fixture(scope='module')
def repertoire():
    return Repertoire.from_archive(load_archive(REPERTOIRE))


@pytest.fixture
def sim():
    with create_simulator(SimConfig(engine='mujoco')) as s:
        yield s


def test_poses_compose_and_invert():
    a = Pose2D(1.0, -2.0, 0.7)
    move = (0.3, -0.4, 0.25)
    b = a.moved(*move)
    assert a.relative(b) == pytest.approx(move)
    assert a.distance_to(1.0, -1.0) == pytest.approx(1.0)


def test_goals_are_checked_with_reasons():
    start, config = Pose2D(0.0, 0.0, 0.0), NavigationConfig(max_range=5.0, arena=2.0)
    assert goal_problem(1.0, 1.0, start, config) == ''
    assert 'not a finite position' in goal_problem(math.nan, 0.0, start, config)
    assert 'beyond the configured range of 5 m' in goal_problem(6.0, 0.0, start, config)
    assert 'outside the arena' in goal_problem(2.5, 0.0, start, config)
    with pytest.raises(ValueError, match='tolerance must be a positive finite number'):
        NavigationConfig(tolerance=0.0)
    with pytest.raises(ValueError, match='optimism must be a finite number >= 0'):
        NavigationConfig(optimism=-1.0)


def test_the_correction_starts_at_the_repertoire_and_learns_a_change_common_to_all_steps(
    repertoire,
):
    gp = CorrectionGP(repertoire, NavigationConfig())
    mean, var = gp.predict()
    np.testing.assert_array_equal(mean[:, :2], repertoire.moves)
    assert np.all(mean[:, 2] == 0) and np.all(var > 0)
    # a damage that halves every step, seen on three steps, is predicted for the others
    lengths = np.hypot(*repertoire.moves.T)
    seen = np.argsort(-lengths)[:3]
    for i in seen:
        gp.add(i, (*(0.5 * repertoire.moves[i]), 0.0))
    mean, _ = gp.predict()
    far = np.argsort(-lengths)[3:50]
    before = np.abs(repertoire.moves[far] - 0.5 * repertoire.moves[far]).sum(axis=1)
    after = np.abs(mean[far, :2] - 0.5 * repertoire.moves[far]).sum(axis=1)
    assert np.median(after) < 0.5 * np.median(before)


def test_the_steered_tripod_walks_the_firmware_direction_nearest_the_goal():
    policy = SteeredTripod()
    step = policy.next_step(Pose2D(0.0, 0.0, math.pi / 2), (-1.0, 0.1))  # goal behind-left
    assert step.gait.crab_angle == pytest.approx(math.pi / 2)  # base frame: +y is world -x
    assert step.duration == step.gait.period


def test_an_intact_robot_reaches_a_goal_and_the_time_limit_ends_a_far_one(repertoire, sim):
    body = SimBody(sim)
    body.start()
    config = NavigationConfig()
    result = run_episode(body, RepertoirePolicy(repertoire, config), (1.2, -0.8), config)
    assert result.reached and result.end.distance_to(1.2, -0.8) <= config.tolerance
    assert result.end == pytest.approx(body.pose())  # the simulator's own pose
    assert 0 < result.efficiency <= 1.0 + 1e-9 and result.path_length >= 1.2
    body.start()
    short = NavigationConfig(time_limit=3.0)
    result = run_episode(body, RepertoirePolicy(repertoire, short), (4.0, 0.0), short)
    assert result.outcome is Outcome.TIME_LIMIT and result.walking_time == pytest.approx(3.0)


def test_the_correction_measurably_reduces_the_prediction_error_on_a_damaged_robot(
    repertoire, sim
):
    sim.set_failed_legs((1, 2))
    errors = {}
    for learn in (False, True):
        config = NavigationConfig(learn=learn, time_limit=40.0)
        policy = RepertoirePolicy(repertoire, config)
        body = SimBody(sim)
        seen = []
        for goal in ((1.5, 0.5), (-1.0, 1.0), (0.5, -1.5)):
            body.start()
            seen += run_episode(body, policy, goal, config).prediction_errors
        errors[learn] = np.median(seen)
    print(
        f'median prediction error, legs 1+2 failed: {errors[False]:.3f} m without, '
        f'{errors[True]:.3f} m with the learned correction'
    )
    assert errors[True] < 0.5 * errors[False]


def test_a_gait_is_played_with_its_own_table_even_if_ids_coincide(sim, monkeypatch):
    # the table cache was keyed by id(): a collected gait's id, reused by a later gait, played
    # the old gait's table, and the experiment's figures changed with the allocator's history.
    # Here every object gets the same id, as a reused one would.
    import hexapod_adapt.navigation as navigation
    from hexapod_gait import build_joint_table, preset

    monkeypatch.setattr(navigation, 'id', lambda obj: 0, raising=False)
    body = SimBody(sim)
    body.start()
    for gait in (
        preset('tripod').replace(crab_angle=0.3),
        preset('wave').replace(crab_angle=-1.0),
    ):
        body.walk(gait, 0.1, lambda p: False)
        first_pose = build_joint_table(gait, rate=1.0 / sim.dt).positions[0]
        np.testing.assert_array_equal(body._rows(gait)[2], first_pose)
