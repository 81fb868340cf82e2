# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The navigator without ROS: poses, goals, the learned correction, the planner, episodes."""

import math
from pathlib import Path

from hexapod_navigation.core.config import goal_problem, NavigationConfig
from hexapod_navigation.core.correction import CorrectionGP
from hexapod_navigation.core.episode import Outcome, run_episode, SimBody
from hexapod_navigation.core.geometry import Pose2D
from hexapod_navigation.core.planner import RepertoirePolicy, rest_speeds, time_to_goal
from hexapod_navigation.core.repertoire import shipped_repertoire
from hexapod_navigation.core.tripod import SteeredTripod
import numpy as np
import pytest

REPERTOIRE = shipped_repertoire()


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
    # before the first pose: all but the range
    assert 'not a finite position' in goal_problem(1.0, math.inf, None, config)
    assert 'outside the arena' in goal_problem(2.5, 0.0, None, config)
    assert goal_problem(1.0, 1.0, None, config) == ''
    with pytest.raises(ValueError, match='tolerance must be a positive finite number'):
        NavigationConfig(tolerance=0.0)
    with pytest.raises(ValueError, match='optimism must be a finite number >= 0'):
        NavigationConfig(optimism=-1.0)


def test_the_correction_starts_at_the_repertoire_and_learns_a_change_common_to_all_steps(
    repertoire,
):
    gp = CorrectionGP(repertoire, NavigationConfig(known_std_xy=0.0))  # one GP for all
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
    from hexapod_gait import build_joint_table, preset
    import hexapod_navigation.core.planner as navigation

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


def test_the_correction_weighs_step_hypotheses_by_their_marginal_likelihood(repertoire):
    from scipy.linalg import solve_triangular

    rng = np.random.default_rng(1)
    config = NavigationConfig(known_std_xy=0.0)  # one GP for all hypotheses
    intact = np.column_stack([repertoire.moves, np.zeros(len(repertoire))])
    truth = intact * np.array([0.6, 0.6, 0.0]) + rng.normal(0, 0.02, intact.shape)
    decoy = intact * np.array([-0.2, 1.0, 0.0])
    gp = CorrectionGP(repertoire, config, np.array([decoy, truth]))
    np.testing.assert_allclose(gp.weights, [1 / 3] * 3)
    seen = [5, 77, 300, 412]
    for i in seen:
        gp.add(i, truth[i])
    # direct: per hypothesis and dimension the GP's residual Mahalanobis norm
    plain = CorrectionGP(repertoire, config)
    for i in seen:
        plain.add(i, truth[i])
    x = plain.inputs[seen]
    se, lin = plain._kernels(x, x)
    logs = []
    for mean in (intact, decoy, truth):
        total = 0.0
        for d in range(3):
            ld = config.linear_std**2 if d < 2 else 0.0
            k = plain.signal[d] * se + ld * lin + plain.noise[d] * np.eye(len(seen))
            w = solve_triangular(np.linalg.cholesky(k), truth[seen, d] - mean[seen, d], lower=True)
            total -= 0.5 * w @ w
        logs.append(total)
    expected = np.exp(np.array(logs) - max(logs))
    np.testing.assert_allclose(gp.weights, expected / expected.sum(), atol=1e-9)
    assert int(np.argmax(gp.weights)) == 2
    # the mixture predicts the unseen steps better than the GP learning alone
    unseen = np.setdiff1d(np.arange(len(repertoire)), seen)
    with_bank = np.abs(gp.predict()[0][unseen, :2] - truth[unseen, :2]).sum(axis=1)
    alone = np.abs(plain.predict()[0][unseen, :2] - truth[unseen, :2]).sum(axis=1)
    assert np.median(with_bank) < 0.5 * np.median(alone)
    # with only the intact repertoire, the same GP as without hypotheses
    none = CorrectionGP(repertoire, config, np.zeros((0, len(repertoire), 3)))
    for i in seen:
        none.add(i, truth[i])
    np.testing.assert_allclose(none.predict()[0], plain.predict()[0], atol=1e-12)
    with pytest.raises(ValueError, match=r'a \(dx, dy, dyaw\) per repertoire step'):
        CorrectionGP(repertoire, config, np.zeros((1, 3, 3)))


def test_time_to_goal_counts_the_switch_the_entry_into_the_goal_circle_and_the_rest():
    ends = np.array([[0.6, 0.0], [0.2, 0.0], [0.0, 0.6]])
    switch = np.array([0.5, 0.0, 0.0])
    t = time_to_goal((0.0, 0.0), ends, (0.4, 0.0), 0.075, 2.0, switch, 0.3)
    # straight through the goal: enters the circle 0.325 m into a 0.6 m step
    assert t[0] == pytest.approx(0.5 + 2.0 * 0.325 / 0.6)
    # short of it: the whole step, then 0.2 - 0.075 m at 0.3 m/s
    assert t[1] == pytest.approx(2.0 + 0.125 / 0.3)
    # sideways: ends 0.72 m away
    assert t[2] == pytest.approx(2.0 + (math.hypot(0.4, 0.6) - 0.075) / 0.3)
    # a start already inside the circle costs only the switch
    inside = time_to_goal((0.39, 0.0), ends, (0.4, 0.0), 0.075, 2.0, switch, 0.3)
    np.testing.assert_allclose(inside, switch)


def test_the_time_planner_keeps_walking_the_gait_it_plays_unless_another_saves_its_switch(
    repertoire,
):
    config = NavigationConfig(planner='time', use_bank=False, tripod_option=False)
    policy = RepertoirePolicy(repertoire, config)
    far = (5.0, 0.0)
    first = policy.next_step(Pose2D(0.0, 0.0, 0.0), far, None, 0.5)
    assert first.duration == pytest.approx(repertoire.step_duration + 0.5)
    # the same gait again: no switch, so it costs only the step
    again = policy.next_step(Pose2D(0.0, 0.0, 0.0), far, first.gait, 0.5)
    assert again.gait is first.gait and again.duration == repertoire.step_duration
    # toward a goal the playing gait walks away from, it switches and pays for it
    back = policy.next_step(Pose2D(0.0, 0.0, 0.0), (-5.0, 0.0), first.gait, 0.5)
    assert back.gait is not first.gait and back.duration == repertoire.step_duration + 0.5
    with pytest.raises(ValueError, match='planner must be one of'):
        NavigationConfig(planner='mcts')
    with pytest.raises(ValueError, match='aim must be a fraction'):
        NavigationConfig(aim=0.0)


def test_a_new_gait_walks_its_whole_step_after_the_transition(repertoire, sim):
    body = SimBody(sim)
    body.start()
    policy = RepertoirePolicy(repertoire, NavigationConfig(use_bank=False))
    step = policy.next_step(body.pose(), (3.0, 0.0), body.playing, body.switch_time)
    assert step.duration == pytest.approx(repertoire.step_duration + body.switch_time)
    outcome = body.walk(step.gait, step.duration, lambda p: False)
    assert outcome.completed and outcome.elapsed == pytest.approx(step.duration)
    assert body.playing is step.gait
    # from rest after the transition, the step goes about as far as the repertoire measured it
    moved = np.hypot(*outcome.start.relative(outcome.end)[:2])
    assert moved == pytest.approx(np.hypot(*repertoire.moves[step.index]), rel=0.25)
    body.halt()
    assert body.playing is None


def test_the_intact_repertoire_may_get_a_prior_weight_among_the_bank_hypotheses(repertoire):
    rng = np.random.default_rng(3)
    bank = repertoire.moves[None] * rng.uniform(0.3, 1.0, (4, 1, 1))
    hypotheses = np.concatenate([bank, np.zeros((4, len(repertoire), 1))], axis=2)
    alike = CorrectionGP(repertoire, NavigationConfig(known_std_xy=0.0), hypotheses)
    np.testing.assert_allclose(alike.weights, 0.2)
    leaning = CorrectionGP(
        repertoire, NavigationConfig(known_std_xy=0.0, prior_intact=0.6), hypotheses
    )
    np.testing.assert_allclose(leaning.weights, [0.6, 0.1, 0.1, 0.1, 0.1])
    # the evidence then moves both alike: the weight ratios of the failures stay equal
    for gp in (alike, leaning):
        gp.add(0, (*hypotheses[1, 0, :2], 0.0))
    ratio = alike.weights[1:] / alike.weights[1]
    np.testing.assert_allclose(leaning.weights[1:] / leaning.weights[1], ratio)
    with pytest.raises(ValueError, match='prior_intact must be a probability'):
        NavigationConfig(prior_intact=1.0)


def test_runs_csv_keeps_how_each_episode_ended_and_reads_older_files(tmp_path):
    import csv
    import hashlib
    import json

    from hexapod_navigation.offline.experiment import (
        NavigationRow,
        NavigationSettings,
        read_rows,
        write_results,
    )

    tipped = NavigationRow(
        'S3', '1+5', 4, 1.0, -2.0, 'repertoire', 'failed', False, 5.0, 1.2, 0.8, 2, 1.9,
        0.05, 'the robot tipped over (roll 71 deg, pitch 3 deg)',
    )  # fmt: skip
    write_results(tmp_path, NavigationSettings(repertoire=REPERTOIRE), [tipped], [[(0.0, 0.0)]])
    assert read_rows(tmp_path / 'runs.csv') == [tipped]
    # the summary names the repertoire by its content too (no bank, no specialists given)
    digests = json.loads((tmp_path / 'summary.json').read_text())['inputs_sha256']
    assert digests == {'repertoire': hashlib.sha256(Path(REPERTOIRE).read_bytes()).hexdigest()}
    # a runs.csv written before the column: the reason reads as unknown
    with open(tmp_path / 'runs.csv', newline='') as src, open(tmp_path / 'old.csv', 'w') as dst:
        csv.writer(dst).writerows(row[:-1] for row in csv.reader(src))
    (old,) = read_rows(tmp_path / 'old.csv')
    assert old.reason == '' and old.outcome == 'failed'


def test_a_method_beats_a_baseline_by_success_then_by_walking_time():
    from hexapod_navigation.offline.experiment import (
        beats,
        MethodSummary,
        scenarios_beating_baselines,
    )

    def row(scenario, method, rate, median):
        return MethodSummary(scenario, method, 10, rate, median, 0.9)

    assert beats(row('S1', 'a', 1.0, 30.0), row('S1', 'b', 0.9, 10.0))
    assert not beats(row('S1', 'a', 0.9, 10.0), row('S1', 'b', 1.0, 30.0))
    assert beats(row('S1', 'a', 1.0, 9.9), row('S1', 'b', 1.0, 10.0))
    assert not beats(row('S1', 'a', 1.0, 10.0), row('S1', 'b', 1.0, 10.0))  # a tie is not better
    assert not beats(row('S1', 'a', 0.0, float('nan')), row('S1', 'b', 0.0, float('nan')))
    summaries = [
        row('S0', 'repertoire', 1.0, 9.0),
        row('S0', 'no_learning', 1.0, 8.5),
        row('S0', 'tripod', 1.0, 9.4),
        row('S1', 'repertoire', 1.0, 12.0),
        row('S1', 'no_learning', 0.9, 10.0),
        row('S1', 'tripod', 1.0, 13.0),
        row('S2', 'repertoire', 1.0, 12.0),
        row('S2', 'tripod', 0.5, 13.0),  # no no_learning row: not counted as beaten
    ]
    assert scenarios_beating_baselines(summaries) == ['S1']
    assert scenarios_beating_baselines(summaries, baselines=('tripod',)) == ['S0', 'S1', 'S2']


def test_known_models_get_a_tight_gp_and_an_unknown_damage_hypothesis_catches_the_rest(
    repertoire,
):
    from scipy.linalg import solve_triangular

    rng = np.random.default_rng(5)
    intact = np.column_stack([repertoire.moves, np.zeros(len(repertoire))])
    bank = np.stack([intact * np.array([0.7, 0.7, 0.0]), intact * np.array([1.0, -0.5, 0.0])])
    config = NavigationConfig(known_std_xy=0.05, prior_unknown=0.2, prior_intact=0.4)
    gp = CorrectionGP(repertoire, config, bank)
    # intact, the bank's two, then 'unknown damage'
    np.testing.assert_allclose(gp.weights, [0.4, 0.2, 0.2, 0.2])
    seen = [5, 77, 300, 412, 600]
    walked = intact + rng.normal(0, 0.01, intact.shape)  # an intact robot
    for i in seen:
        gp.add(i, walked[i])
    # direct: each hypothesis's Gaussian log likelihood under its own kernel, determinant included
    x = gp.inputs[seen]
    se, lin = gp._kernels(x, x)
    tight = np.array([0.05, 0.05, 0.15]) ** 2
    logs = []
    for mean, signal, linear in (
        (intact, tight, 0.0),
        (bank[0], tight, 0.0),
        (bank[1], tight, 0.0),
        (intact, gp.signal, config.linear_std**2),
    ):
        total = 0.0
        for d in range(3):
            k = signal[d] * se + (linear * lin if d < 2 else 0) + gp.noise[d] * np.eye(len(seen))
            chol = np.linalg.cholesky(k)
            w = solve_triangular(chol, walked[seen, d] - mean[seen, d], lower=True)
            total -= 0.5 * w @ w + np.sum(np.log(np.diag(chol)))
        logs.append(total)
    expected = np.array([0.4, 0.2, 0.2, 0.2]) * np.exp(np.array(logs) - max(logs))
    np.testing.assert_allclose(gp.weights, expected / expected.sum(), atol=1e-9)
    assert gp.weights[0] > 0.9  # the intact robot is recognised ...
    broad = CorrectionGP(repertoire, NavigationConfig(known_std_xy=0.0, prior_intact=0.4), bank)
    for i in seen:
        broad.add(i, walked[i])
    assert broad.weights[0] < gp.weights[0] - 0.25  # ... better than under one broad GP for all
    # damage that no known model describes: the 'unknown damage' hypothesis takes over
    odd = CorrectionGP(repertoire, config, bank)
    turned = intact * np.array([-0.3, 0.4, 0.0])
    for i in seen:
        odd.add(i, turned[i])
    assert int(np.argmax(odd.weights)) == 3 and odd.weights[3] > 0.9
    with pytest.raises(ValueError, match='must leave the bank some weight'):
        NavigationConfig(known_std_xy=0.05, prior_intact=0.5, prior_unknown=0.5)
    with pytest.raises(ValueError, match='known_std_xy must be'):
        NavigationConfig(known_std_xy=-1.0)


def test_the_experiment_can_walk_damage_of_another_kind_than_the_banks():
    from hexapod_navigation.offline.experiment import _case, NavigationSettings

    with pytest.raises(ValueError, match="unknown damage kind 'bent'"):
        NavigationSettings(repertoire=REPERTOIRE, damage_kind='bent')
    paths = {}
    for kind in ('lifted', 'locked'):
        settings = NavigationSettings(
            repertoire=REPERTOIRE, goals=1, methods=('no_learning',), damage_kind=kind
        )
        ((row, path),) = _case(settings, 'S3', (1, 5))
        assert row.failed_legs == '1+5' and row.steps >= 1
        paths[kind] = np.array(path)
    # the same plan, walked with the legs held up or locked where they stood: other paths
    n = min(len(paths['lifted']), len(paths['locked']))
    assert np.max(np.abs(paths['lifted'][:n] - paths['locked'][:n])) > 0.01


def test_unknown_optimism_grows_with_the_weight_of_unknown_damage(repertoire):
    intact = np.column_stack([repertoire.moves, np.zeros(len(repertoire))])
    bank = intact[None] * np.array([0.7, 0.7, 0.0])
    start, goal = Pose2D(0.0, 0.0, 0.0), (2.0, 1.0)
    plain = RepertoirePolicy(repertoire, NavigationConfig(), bank)
    eager = RepertoirePolicy(repertoire, NavigationConfig(unknown_optimism=50.0), bank)
    # before any step 'unknown damage' has its prior weight only
    assert plain.gp.unknown_weight == pytest.approx(0.2)
    # steps that no known model predicts: 'unknown damage' takes the weight, and the optimism
    # it brings changes the choice
    for policy in (plain, eager):
        for i in (5, 77, 300):
            policy.gp.add(i, intact[i] * np.array([-0.2, 0.1, 0.0]))
    assert eager.gp.unknown_weight > 0.99
    assert plain.next_step(start, goal).index != eager.next_step(start, goal).index
    one_gp = RepertoirePolicy(repertoire, NavigationConfig(known_std_xy=0.0), bank)
    assert one_gp.gp.unknown_weight == 0.0  # no such hypothesis under one GP
    with pytest.raises(ValueError, match='unknown_optimism must be'):
        NavigationConfig(unknown_optimism=-1.0)


def test_the_rest_of_the_way_at_the_speed_toward_the_goal_breaks_marking_time(repertoire):
    # damage that leaves long sideways steps but short forward ones; the playing gait barely
    # moves. Counting the rest of the way at the longest step's speed (any direction), the
    # transition to a gait that gains 7 cm costs more than it saves: the robot marks time
    goal, start = (0.6, 0.0), Pose2D(0.0, 0.0, 0.0)
    mean = np.column_stack([repertoire.moves * np.array([0.15, 1.0]), np.zeros(len(repertoire))])
    choices = {}
    for rest in ('fastest', 'toward'):
        config = NavigationConfig(use_bank=False, rest_speed=rest, tripod_option=False)
        policy = RepertoirePolicy(repertoire, config)
        stuck = int(np.flatnonzero(policy.allowed)[0])
        crafted = mean.copy()
        crafted[stuck] = (0.003, 0.0, 0.0)
        policy.gp.predict = lambda m=crafted: (m, np.full_like(m, 1e-4))
        playing = policy.repertoire.gait(stuck)
        policy._gaits[stuck] = playing
        choices[rest] = policy.next_step(start, goal, playing, 0.5).index
    assert choices['fastest'] == stuck  # marks time
    assert choices['toward'] != stuck  # takes the transition to a step that heads for the goal
    with pytest.raises(ValueError, match='rest_speed must be one of'):
        NavigationConfig(rest_speed='slowest')


def test_rest_speeds_walk_the_rest_by_the_own_gait_or_after_a_change_whichever_is_sooner():
    ends = np.array([[0.0, 0.0], [0.0, 0.0], [2.95, 0.0]])
    goal, radius, step, switch = (3.0, 0.0), 0.1, 2.0, 0.5
    progress = np.array([0.4, 0.02, 0.3])
    speed = rest_speeds(ends, goal, radius, progress, 0.4, step, switch)
    # the best gait itself: its own pace, no change
    assert speed[0] == pytest.approx(0.2)
    # a gait that barely moves: a change to the best one, then its pace
    assert speed[1] == pytest.approx(2.9 / (0.5 + 2.9 / 0.2))
    # nothing left to walk: any speed gives the same time; the best's
    assert speed[2] == pytest.approx(0.2)
    # time_to_goal takes a speed per step
    t = time_to_goal((0.0, 0.0), ends, goal, radius, step, np.zeros(3), speed)
    assert t[1] == pytest.approx(step + 0.5 + 2.9 / 0.2)


def test_counting_the_change_to_the_faster_gait_changes_to_it_now(repertoire):
    # the playing gait makes 0.35 m a step toward a goal 3 m away, another 0.40 m. Walking the
    # rest of the way at 0.40 m a step for free, the playing gait looks best (no transition
    # now); counting the transition the robot must then make, the faster one is taken now
    goal, start = (3.0, 0.0), Pose2D(0.0, 0.0, 0.0)
    choices = {}
    for rest_switch in (False, True):
        config = NavigationConfig(use_bank=False, tripod_option=False, rest_switch=rest_switch)
        policy = RepertoirePolicy(repertoire, config)
        playing_i, fast_i = (int(i) for i in np.flatnonzero(policy.allowed)[:2])
        crafted = np.zeros((len(repertoire), 3))
        crafted[:, 0] = 0.01
        crafted[playing_i] = (0.35, 0.0, 0.0)
        crafted[fast_i] = (0.40, 0.0, 0.0)
        policy.gp.predict = lambda m=crafted: (m, np.full_like(m, 1e-4))
        playing = policy.repertoire.gait(playing_i)
        policy._gaits[playing_i] = playing
        choices[rest_switch] = policy.next_step(start, goal, playing, 0.5).index
    assert choices[False] == playing_i
    assert choices[True] == fast_i


def test_the_tripod_option_learns_its_cycles_and_takes_over_when_the_repertoire_lags(repertoire):
    from hexapod_navigation.core.tripod import TripodSteps

    tripod = TripodSteps()
    stride = tripod.displacement()
    assert stride[0, 0] > 0.05 and abs(stride[0, 1]) < 1e-12  # forward: the commanded stride
    assert stride[2, 1] == pytest.approx(stride[0, 0])  # direction 2 walks to the left
    tripod.observe(0, (0.02, 0.0, 0.0))  # a damaged cycle: 2 cm
    after = tripod.displacement()
    assert after[0, 0] < stride[0, 0] and after[2, 1] < stride[2, 1]  # every direction learns
    # a damage the repertoire has no step for: its step went nowhere, so the tripod takes over
    goal, start = (1.0, 0.0), Pose2D(0.0, 0.0, 0.0)
    policy = RepertoirePolicy(repertoire, NavigationConfig(use_bank=False, tripod_after=1))
    first = policy.next_step(start, goal, None, 0.5)
    assert first.tripod == -1  # the repertoire gets its chance first
    policy.observe(first, start, Pose2D(0.005, 0.0, 0.0), True)
    second = policy.next_step(Pose2D(0.005, 0.0, 0.0), goal, first.gait, 0.5)
    assert second.tripod == 0 and second.gait.crab_angle == 0.0  # the cycle toward the goal
    policy.observe(second, Pose2D(0.005, 0.0, 0.0), second.predicted, True)
    # where the repertoire's step did go, it keeps walking it
    policy = RepertoirePolicy(repertoire, NavigationConfig(use_bank=False, tripod_after=1))
    first = policy.next_step(start, goal, None, 0.5)
    policy.observe(first, start, first.predicted, True)
    assert policy.next_step(first.predicted, goal, first.gait, 0.5).tripod == -1
    off = RepertoirePolicy(repertoire, NavigationConfig(use_bank=False, tripod_option=False))
    step = off.next_step(start, goal, None, 0.5)
    off.observe(step, start, start, True)
    assert off.next_step(start, goal, step.gait, 0.5).tripod == -1
    with pytest.raises(ValueError, match='tripod_after must be'):
        NavigationConfig(tripod_after=-1)


def test_tripod_cycles_weigh_the_damage_hypotheses_and_set_the_tripods_prior(repertoire):
    """A cycle walked like hypothesis 2's makes it likelier; the tripod's prior follows it."""
    rng = np.random.default_rng(5)
    steps = rng.normal(0.0, 0.05, (3, len(repertoire), 3))
    intact = np.zeros((8, 3))
    intact[:, 0] = 0.3  # every direction's cycle, as its own 'forward' (a made-up table)
    tripods = np.stack([intact, intact * 0.9, intact * 0.2, intact * 0.5])
    gp = CorrectionGP(
        repertoire, NavigationConfig(tripod_bank='always', tripod_after=0), steps, tripods
    )
    before = gp.tripod_prior()
    assert before.shape == (8, 3) and 0.06 < before[0, 0] < 0.3  # the prior's mixture
    gp.add_tripod(0, (0.06, 0.0, 0.0))
    gp.add_tripod(0, (0.06, 0.0, 0.0))
    assert np.argmax(gp.weights) == 2  # hypothesis 2 (row 2 of the table, steps[1])
    assert gp.tripod_prior()[3, 0] == pytest.approx(0.06, abs=0.02)  # every direction follows
    with pytest.raises(ValueError, match='tripods needs'):
        CorrectionGP(repertoire, NavigationConfig(), steps, tripods[:3])
    # 'off' passes no table to the policy's GP: the fixed stride prior
    off = NavigationConfig(tripod_bank='off')
    assert RepertoirePolicy(repertoire, off, steps, tripods).gp.tripod_prior() is None
    # the policy's tripod option starts from that prior ('always'): here, a pessimistic one
    poor = np.stack([intact * 0.1] * 4)
    policy = RepertoirePolicy(
        repertoire, NavigationConfig(tripod_bank='always', tripod_after=0), steps, poor
    )
    start, goal = Pose2D(0.0, 0.0, 0.0), (1.0, 0.0)
    assert policy.next_step(start, goal, None, 0.5).tripod == -1  # 3 cm do not beat a step
    # 'evidence': the commanded stride until something was walked, then the bank
    policy = RepertoirePolicy(
        repertoire, NavigationConfig(tripod_bank='evidence', tripod_after=0), steps, poor
    )
    first = policy.next_step(start, goal, None, 0.5)
    assert first.tripod == 0
    policy.observe(first, start, start.moved(0.03, 0.0, 0.0), True)
    assert policy.gp.evidence == 1
    assert policy.next_step(start.moved(0.03, 0.0, 0.0), goal, first.gait, 0.5).tripod == -1
    # a report of a damage the bank models: evidence too with tripod_reported, so the first
    # cycle is weighed under the bank (3 cm: a step wins); without it, the commanded stride
    for told, expected in ((True, -1), (False, 0)):
        config = NavigationConfig(tripod_bank='evidence', tripod_after=0, tripod_reported=told)
        policy = RepertoirePolicy(repertoire, config, steps, poor, reported=2)
        assert policy.gp.evidence == 0
        assert policy.next_step(start, goal, None, 0.5).tripod == expected
    with pytest.raises(ValueError, match='tripod_bank must be one of off, always, evidence'):
        NavigationConfig(tripod_bank='sometimes')
    always = NavigationConfig(tripod_bank='always', tripod_after=0)
    optimistic = RepertoirePolicy(repertoire, always, steps, np.stack([intact] * 4))
    assert optimistic.gp.tripod_prior()[0, 0] == pytest.approx(0.3)


def test_a_reported_damage_the_bank_models_is_favoured_and_a_dead_coxa_is_a_folded_leg(
    repertoire,
):
    from hexapod_navigation.core.step_bank import reported_note, StepBank
    from hexapod_sim.damage import Damage

    damages = (Damage.lifted([1]), Damage.of('unpowered_femur', [2]), Damage.of('locked', [3]))
    rng = np.random.default_rng(2)
    bank = StepBank(
        damages,
        rng.normal(0.0, 0.05, (3, len(repertoire), 3)),
        rng.normal(size=(3, 8, 3)),
        rng.normal(size=(8, 3)),
    )
    # the fold policy folds a leg with a dead coxa as a lifted one
    assert bank.index_of(Damage.of('unpowered_coxa', [1])) == 0
    assert bank.index_of(Damage.of('unpowered_femur', [2])) == 1
    assert bank.index_of(Damage.of('unpowered_tibia', [1])) is None
    assert bank.index_of(Damage.of('unpowered_coxa', [4])) is None
    known = 1 + len(damages)  # intact first
    config = NavigationConfig()
    femur = RepertoirePolicy.with_bank(repertoire, config, bank, damages[1])
    weights = femur.gp.weights  # before any step: the prior
    rest = 1.0 - config.prior_unknown
    share = config.prior_reported
    assert weights[2] == pytest.approx(rest * (share + (1.0 - share) / known))
    assert weights[1] == pytest.approx(rest * (1.0 - share) / known)
    assert weights.sum() == pytest.approx(1.0)
    plain = RepertoirePolicy.with_bank(repertoire, config, bank, Damage.of('weak', [5]))
    assert plain.gp.weights[:known] == pytest.approx([rest / known] * known)
    off = RepertoirePolicy.with_bank(
        repertoire, NavigationConfig(prior_reported=0.0), bank, damages[1]
    )
    assert off.gp.weights[:known] == pytest.approx([rest / known] * known)
    with pytest.raises(ValueError, match='prior_reported must be a share in'):
        NavigationConfig(prior_reported=1.0)
    with pytest.raises(ValueError, match='reported must name one of the 3 hypotheses'):
        CorrectionGP(repertoire, config, bank.steps, reported=0)
    # what the log says of a report
    assert "favours the damage bank's leg 1 lifted" in reported_note(
        bank, Damage.of('unpowered_coxa', [1]), 0.5
    )
    tibia = Damage.of('unpowered_tibia', [1])
    assert 'does not model leg 1 unpowered tibia' in reported_note(bank, tibia, 0.5)
    assert 'no damage bank' in reported_note(None, tibia, 0.5)
    assert 'prior_reported is 0' in reported_note(bank, tibia, 0.0)
