# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The tip guard of adaptation trials: a gait that tips is a failed trial, never tried again."""

from dataclasses import replace
import math

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.online.adaptation import (
    DEFAULT_TIP_GUARD,
    simulated_trial,
    tipped_outcome,
    TrialOutcome,
)
from hexapod_adapt.online.mboa import Mboa, MboaConfig
from hexapod_adapt.online.session import adapt, AdaptationSession, run_session, SessionStart
from hexapod_adapt.online.trials import OdomLog, OdomSample, TiltLog, TiltSample
from hexapod_gait import preset
import numpy as np
import pytest

#: The gait of each niche, as adapt_node's archive gives it (its archive_index set).
GAITS = lambda niche: preset('tripod').replace(archive_index=niche)  # noqa: E731


def _archive(n=50, seed=3):
    rng = np.random.default_rng(seed)
    a = Archive.empty(rng.random((n, 6)))
    a.fitness[:] = rng.uniform(0.5, 2.0, n)
    a.descriptors[:] = a.centroids
    a.genotypes[:] = rng.random((n, 32))
    return a


def test_the_default_guard_is_half_the_tip_over_line():
    from hexapod_sim.simulator import TIP_OVER_DEG

    assert DEFAULT_TIP_GUARD == pytest.approx(math.radians(TIP_OVER_DEG) / 2)


def test_a_tilt_past_the_guard_is_a_failed_trial_and_below_it_is_none():
    assert tipped_outcome(0.6, 0.5) == TrialOutcome(0.0, True, 0.6)
    assert tipped_outcome(0.4, 0.5) is None
    assert tipped_outcome(float('nan'), 0.5) is None


@pytest.mark.parametrize('exclude_tested', [True, False])
def test_a_gait_that_tipped_counts_zero_and_is_never_tried_again(exclude_tested):
    a = _archive()
    best = int(np.argmax(a.speeds()))  # the prior's first choice tips
    tried = []

    def trial(niche):
        tried.append(niche)
        if niche == best:
            return TrialOutcome(0.42, tipped=True, peak_tilt=1.2)  # the speed is not believed
        return TrialOutcome(0.5 * a.speeds()[niche], False, 0.1)

    config = replace(MboaConfig(max_trials=8), exclude_tested=exclude_tested, alpha=0.99)
    result = adapt(a, trial, config)
    assert tried[0] == best and tried.count(best) == 1
    assert result.tipped == [best]
    first = result.trials[0]
    assert first.tipped and first.measured == 0.0
    assert not any(t.tipped for t in result.trials[1:])
    assert result.best_niche != best


def test_mboa_excludes_a_tipped_candidate_even_when_retesting_is_allowed():
    config = replace(MboaConfig(), exclude_tested=False)
    opt = Mboa(np.random.default_rng(0).random((3, 6)), np.array([0.3, 0.2, 0.1]), config)
    opt.observe(0, 0.0, tipped=True)
    assert opt.excluded() == {0} and opt.next_index() != 0
    opt.observe(1, 0.05)
    assert opt.excluded() == {0} and opt.next_index() in (1, 2)  # 1 may be tried again


def test_mboa_never_picks_a_vetoed_candidate_and_stops_when_all_are_vetoed_or_tried():
    from hexapod_adapt.online.mboa import StopReason

    opt = Mboa(np.random.default_rng(0).random((3, 6)), np.array([0.3, 0.2, 0.1]))
    opt.veto(0)
    assert opt.next_index() != 0 and opt.leading_index() == 1 and opt.excluded() == {0}
    with pytest.raises(ValueError, match='candidate 3 does not exist'):
        opt.veto(3)
    opt.veto(2)
    assert opt.stop_reason() is StopReason.CONTINUE and opt.next_index() == 1
    opt.veto(1)
    assert opt.leading_index() is None and opt.stop_reason() is StopReason.MAP_EXHAUSTED
    assert 'tried or vetoed (3)' in opt.should_stop()[1]


def test_a_newer_prior_keeps_the_tipped_trials_tipped():
    """A re-score streaming in restarts M-BOA: a tipped trial stays a tip, never tried again."""
    a = _archive()
    prior = a.speeds()[a.elite_indices()].copy()
    best = int(a.elite_indices()[int(np.argmax(prior))])
    tried = []

    def trial(niche):
        tried.append(niche)
        if niche == best:
            return TrialOutcome(0.0, True, 1.2)
        return TrialOutcome(0.1 * a.speeds()[niche], False, 0.1)

    config = replace(MboaConfig(max_trials=8), exclude_tested=False)
    result = adapt(a, trial, config, SessionStart(prior, lambda: prior))
    assert tried[0] == best and tried.count(best) == 1 and result.tipped == [best]
    assert result.trials[0].tipped


def test_a_tipped_gait_is_never_the_best_left_on_the_robot():
    """CI: a run that aborted after its only trial tipped left that gait playing, as its best."""
    a = _archive()
    best = int(np.argmax(a.speeds()))

    def trial(niche):  # the first tips, every other walks backwards
        return TrialOutcome(0.0, True, 1.2) if niche == best else TrialOutcome(-0.05, False, 0.1)

    only = adapt(a, trial, MboaConfig(max_trials=1))
    assert only.tipped == [best] and only.best_niche == -1  # nothing to leave walking
    more = adapt(a, trial, MboaConfig(max_trials=3))
    assert more.best_niche not in (-1, best) and more.best_speed == -0.05
    opt = Mboa(np.random.default_rng(0).random((2, 6)), np.array([0.3, 0.2]), MboaConfig())
    opt.observe(0, 0.0, tipped=True)
    assert opt.best() is None


def test_a_simulated_trial_past_the_guard_tips_and_below_it_walks():
    from hexapod_gait import preset
    from hexapod_gait.parameters import to_genotype
    from hexapod_sim import create_simulator

    a = Archive.empty(np.full((1, 6), 0.5))
    a.fitness[0], a.descriptors[0], a.genotypes[0] = 1.0, 0.5, to_genotype(preset('control'))
    with create_simulator() as sim:
        walked = simulated_trial(a, [1], sim)(0)
        assert not walked.tipped and walked.speed > 0.05 and 0 < walked.peak_tilt < 0.5
        # the control tripod rocks the body a little: a guard below that rocking stops it
        guarded = simulated_trial(a, [1], sim, tip_guard=0.5 * walked.peak_tilt)(0)
        assert guarded.tipped and guarded.speed == 0.0
        assert guarded.peak_tilt == pytest.approx(walked.peak_tilt)


def test_the_logs_give_the_peak_tilt_of_a_trial():
    odom = OdomLog()
    for k, tilt in enumerate([0.1, 0.7, 0.2]):
        odom.append(OdomSample(1000 + k, 0.0, 0.0, 0.0, 0.0, float(k), tilt=tilt))
    assert odom.peak_tilt_after(999) == pytest.approx(0.7)
    assert odom.peak_tilt_after(1001) == pytest.approx(0.2)
    assert odom.peak_tilt_after(1002) == 0.0
    assert odom.peak_tilt_after(5000) == 0.0
    tilts = TiltLog()
    for k, tilt in enumerate([0.9, 0.1, 0.3]):
        tilts.append(TiltSample(tilt, float(k)))
    assert tilts.peak_since(0.5) == pytest.approx(0.3)


def test_a_robot_trial_that_tilts_past_the_guard_is_stopped_through_the_bridge():
    import time

    from hexapod_adapt.online.trials import RobotTrials, SampleLog, TrialTiming, Upload, Waiter

    class Robot:
        stopped = 0

        def upload(self, gait, timeout):
            return Upload(True, '', gait.archive_index), 0.0

        def start_trial(self):
            return True, ''

        def stop_trial(self):
            Robot.stopped += 1
            return True, ''

    tilts = TiltLog()
    # the IMU reports the body rolling over after the trial started (no odometry comes)
    tilts.append(TiltSample(0.9, time.monotonic() + 60.0))
    trials = RobotTrials(
        GAITS,
        Robot(),
        SampleLog(),
        Waiter(lambda: True, poll=0.001),
        TrialTiming(duration=5.0, timeout=5.0, stand_still=0.0),
        lambda: '',
        print,
        max_speed=4.8,
        tilts=tilts,
        tip_guard=0.5,
    )
    outcome = trials(3)
    assert outcome.tipped and outcome.speed == 0.0 and outcome.peak_tilt == pytest.approx(0.9)
    assert Robot.stopped == 1


def test_a_robot_lying_past_the_guard_is_righted_before_its_next_trial_starts():
    """A trial that tipped leaves the robot on its side: the next one asks, and waits."""
    import time

    from hexapod_adapt.online.trials import (
        RobotTrialResult,
        RobotTrials,
        SampleLog,
        TrialAborted,
        TrialTiming,
        Upload,
        Waiter,
    )

    results, tilts, started, asked = SampleLog(), TiltLog(), [], []

    class Robot:
        """The bridge: each trial it starts ends with odometry at once."""

        def upload(self, gait, timeout):
            return Upload(True, '', gait.archive_index), 0.0

        def start_trial(self):
            started.append(time.monotonic())
            results.append(RobotTrialResult(True, False, '', 0.2, 0.0, time.monotonic() + 0.01))
            return True, ''

    def operator(message: str) -> None:  # puts the robot back on its feet when asked
        asked.append(message)
        tilts.append(TiltSample(0.05, time.monotonic()))

    def trials(prompt, righting_timeout=5.0):
        return RobotTrials(
            GAITS,
            Robot(),
            results,
            Waiter(lambda: True, poll=0.001),
            TrialTiming(duration=5.0, timeout=5.0, stand_still=0.0),
            lambda: '',
            prompt,
            max_speed=4.8,
            tilts=tilts,
            tip_guard=0.5,
            righting_timeout=righting_timeout,
        )

    tilts.append(TiltSample(2.8, time.monotonic()))  # on its back after the last trial
    outcome = trials(operator)(4)
    assert not outcome.tipped and outcome.speed == pytest.approx(0.2)
    assert len(asked) == 1 and 'lies tilted 160 deg, past the 29 deg tip guard' in asked[0]
    assert started and started[0] >= tilts.snapshot()[-1].received  # not before it stood
    # upright: no question; lying with nobody to right it: the run is told why, nothing started
    trials(operator)(4)
    assert len(asked) == 1 and len(started) == 2
    tilts.append(TiltSample(1.0, time.monotonic()))
    with pytest.raises(TrialAborted, match='back on its feet'):
        trials(asked.append, righting_timeout=0.05)(4)
    assert len(started) == 2


def _screen(tilts: np.ndarray, guard: float = 0.5):
    from hexapod_adapt.online.prior import TipScreen

    walked: list[list[int]] = []

    def tilts_of(positions):
        walked.append([int(i) for i in positions])
        return tilts[positions]

    return TipScreen(tilts_of, guard), walked


def test_a_tip_screen_walks_each_gait_once_when_first_asked():
    tilts = np.array([0.1, 0.9, 0.2, 0.8, 0.1, 0.1])  # gaits 1 and 3 tip past 0.5
    screen, walked = _screen(tilts)
    assert screen.tips(1) and not screen.tips(2) and screen.tips(1)
    assert walked == [[1], [2]]  # gait 1 was not walked twice
    assert screen.tipping == [1] and screen.tilts == {1: 0.9, 2: 0.2}
    # the fastest upright gait: down from the fastest, walking only as far as needed
    speeds = np.array([0.1, 0.5, 0.4, 0.3, 0.2, 0.05])
    assert screen.best_upright(speeds) == 2 and walked == [[1], [2]]
    every, _ = _screen(np.ones(3))
    assert every.best_upright(np.array([0.3, 0.1, 0.2])) is None and every.tipping == [0, 1, 2]


def test_adapt_never_tries_a_gait_the_screen_says_tips_however_late_it_is_picked():
    """Every pick is vetted, not only the prior's head: half the gaits tip, none is tried."""
    a = _archive()
    prior = a.speeds()[a.elite_indices()].copy()
    order = np.argsort(-prior)
    tilts = np.zeros(len(prior))
    tilts[order[::2]] = 1.0  # the fastest, the third fastest, ...: every other gait tips
    tipping = {int(a.elite_indices()[i]) for i in order[::2]}
    tried = []

    def trial(niche):
        tried.append(niche)
        return TrialOutcome(0.1 * a.speeds()[niche], False, 0.1)  # slow: alpha is never met

    for update in (None, lambda: prior):  # a newer prior (a re-score streaming in) too
        tried.clear()
        screen, walked = _screen(tilts)
        start = SessionStart(prior, update, screen)
        session = AdaptationSession(a, MboaConfig(max_trials=12), start)
        result = run_session(session, trial)
        heard = [(v.niche, v.tilt) for v in session.new_vetoes()]
        assert heard == [(niche, 1.0) for niche in result.vetoed]
        assert len(tried) == 12 and not tipping & set(tried)
        assert set(result.vetoed) <= tipping and len(set(result.vetoed)) == len(result.vetoed)
        assert result.vetoed[0] == int(a.elite_indices()[order[0]])
        assert result.tipped == [] and sum(map(len, walked)) == len(screen.tilts)


def test_a_vetoed_gait_sets_no_bar_for_alpha():
    """The fastest prior gait tips: a trial at alpha x the next one's speed ends the run."""
    a = _archive()
    prior = a.speeds()[a.elite_indices()].copy()
    first, second = np.argsort(-prior)[:2]
    prior *= 0.5  # every other gait: at most half the fastest
    prior[first], prior[second] = 2 * prior[first], 1.8 * prior[first]
    tilts = np.zeros(len(prior))
    tilts[first] = 1.0
    config = replace(MboaConfig(max_trials=10), alpha=0.95)
    speed = 0.96 * prior[second]  # alpha x the second, below alpha x the first

    def trial(niche):
        return TrialOutcome(speed, False, 0.1)

    screen, _ = _screen(tilts)
    result = adapt(a, trial, config, SessionStart(prior, screen=screen))
    assert result.success and len(result.trials) == 1, result.message
    assert result.vetoed == [int(a.elite_indices()[first])]
    assert result.trials[0].index == second
    # the same trial without the veto: the first gait's speed is the bar, and it is not met
    opt = Mboa(a.descriptors[a.elite_indices()], prior, config)
    opt.observe(int(second), speed)
    assert not opt.alpha_met() and opt.leading_index() == first
    opt.veto(int(first))
    assert opt.alpha_met() and opt.leading_index() != first and first in opt.excluded()


def test_the_screen_walks_a_gait_as_a_guarded_trial_does():
    """The tilt the screen reads is the trial's: the same gait, damage and physics."""
    from hexapod_adapt.mapping.simulation import map_physics
    from hexapod_adapt.online.prior import simulated_tilts, TipScreen
    from hexapod_adapt.online.session import screen_note
    from hexapod_gait import preset
    from hexapod_gait.parameters import to_genotype
    from hexapod_sim import create_simulator
    from hexapod_sim.damage import Damage

    a = Archive.empty(np.full((1, 6), 0.5))
    a.fitness[0], a.descriptors[0], a.genotypes[0] = 1.0, 0.5, to_genotype(preset('control'))
    damage = Damage.of('lifted', [1])
    with create_simulator(map_physics(a, 'mujoco')) as sim:
        walked = simulated_trial(a, damage, sim)(0)
    tilt = simulated_tilts(a, damage, 'mujoco')(np.array([0]))
    assert tilt[0] == pytest.approx(walked.peak_tilt)
    # a guard below the tripod's rocking: the screen says it tips, as the trial would stop it
    low = TipScreen(simulated_tilts(a, damage, 'mujoco'), 0.5 * walked.peak_tilt)
    assert low.tips(0) and low.tilts[0] == pytest.approx(walked.peak_tilt)
    assert not TipScreen(simulated_tilts(a, damage, 'mujoco'), 2.0 * walked.peak_tilt).tips(0)
    guard = math.degrees(low.guard)
    assert f'past the {guard:.0f} deg tip guard is never tried' in screen_note(low)
