# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The trial procedures of adapt_node without ROS: a port that behaves like the graph.

The same procedures run through the real graph in tests/graph/test_adapt_graph.py; here each rule
is pinned down on its own, including the faults a loaded graph produces (lost samples, refusals, a
node that never answers).
"""

from __future__ import annotations

import itertools
import math

from hexapod_adapt.online.adaptation import TrialAborted, TrialCancelled
from hexapod_adapt.online.trials import (
    along,
    ManualTrials,
    OdomLog,
    OdomSample,
    RobotTrialResult,
    RobotTrials,
    SampleLog,
    sim_trial_speed,
    SimTrials,
    TrialTiming,
    Upload,
    Waiter,
)
from hexapod_gait import preset
import pytest

#: The gait of each niche, as adapt_node's archive gives it (its archive_index set).
GAITS = lambda niche: preset('tripod').replace(archive_index=niche)  # noqa: E731

SECOND = 1_000_000_000


class FakeClock:
    """Time that moves only when the code under test sleeps."""

    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t

    def sleep(self, dt: float) -> None:
        self.t += dt


def _waiter(clock: FakeClock, check=None) -> Waiter:
    return Waiter(lambda: True, check, clock=clock, sleep=clock.sleep)


class SimGraph:
    """sim_node as a trial sees it: plays the published gait, resets, streams odometry."""

    def __init__(self, odom: OdomLog, speed: float, crab: float = 0.0, lose=(), lag=0.0):
        self.odom, self.speed, self.crab = odom, speed, crab
        self.lag = lag  # s the robot takes to get going after the reset
        self.lose = set(lose)  # attempts whose end sample is lost in transport
        self.stamps = itertools.count(1)
        self.now = 100 * SECOND
        self.attempt = 0
        self._active = self._reset = None
        self.refuse_reset = ''

    def publish_gait(self, gait):
        stamp = next(self.stamps)
        self._active = stamp  # played at once
        return stamp, self.crab

    def active_stamp(self):
        return self._active

    def reset_stamp(self):
        return self._reset

    def reset(self):
        if self.refuse_reset:
            return False, self.refuse_reset
        self.attempt += 1
        self._reset = self.now
        for k in range(0, 51):  # 10 Hz of sim time for 5 s, starting at the reset
            t = self.now + k * SECOND // 10
            if k == 50 and self.attempt in self.lose:
                continue
            d = self.speed * max(0.0, k / 10 - self.lag)
            self.odom.append(
                OdomSample(t, d * math.cos(self.crab), d * math.sin(self.crab), 0, 0, 0.0)
            )
        self.now += 60 * SECOND
        if self.attempt in self.lose:  # a later sample arrives, so the trial knows it is over
            self.odom.append(OdomSample(self.now, 0, 0, 0, 0, 0.0))
        return True, ''


def test_along_projects_on_the_walking_direction():
    assert along(1.0, 0.0, 0.0) == 1.0
    assert along(0.0, 2.0, math.pi / 2) == pytest.approx(2.0)
    assert along(1.0, 1.0, math.pi) == pytest.approx(-1.0)


def test_sim_trial_speed_needs_both_samples():
    samples = [OdomSample(0, 0.0, 0.0, 0, 0, 0), OdomSample(5 * SECOND, 1.5, 0.0, 0, 0, 0)]
    assert sim_trial_speed(samples, 0, 5.0, 0.0) == pytest.approx(0.3)
    assert sim_trial_speed(samples[:1], 0, 5.0, 0.0) is None
    assert sim_trial_speed(samples[1:], 0, 5.0, 0.0) is None


@pytest.mark.parametrize('crab', [0.0, 0.5, -2.0])
def test_a_sim_trial_measures_along_the_gait_direction(crab):
    clock, odom = FakeClock(), OdomLog()
    graph = SimGraph(odom, speed=0.25, crab=crab)
    trial = SimTrials(GAITS, graph, odom, _waiter(clock), TrialTiming(5.0, 10.0), warn=print)
    assert trial(7).speed == pytest.approx(0.25)


def test_a_settled_sim_trial_times_only_the_walk_after_the_settling():
    clock, odom = FakeClock(), OdomLog()
    graph = SimGraph(odom, speed=0.3, lag=0.8)  # standing for 0.8 s, then 0.3 m/s
    settled = SimTrials(
        GAITS, graph, odom, _waiter(clock), TrialTiming(2.0, 10.0, settle=1.0), print
    )
    assert settled.timing.walking == 3.0
    assert settled(4).speed == pytest.approx(0.3)
    from_standing = SimTrials(GAITS, graph, odom, _waiter(clock), TrialTiming(5.0, 10.0), print)
    assert from_standing(4).speed == pytest.approx(0.3 * (5.0 - 0.8) / 5.0)
    samples = [OdomSample(k * SECOND, 0.1 * k * k, 0.0, 0, 0, 0) for k in range(4)]
    assert sim_trial_speed(samples, 0, 2.0, 0.0, settle=1.0) == pytest.approx((0.9 - 0.1) / 2)
    assert sim_trial_speed(samples, 0, 2.0, 0.0, settle=0.5) is None  # no sample at 0.5 s


def test_a_lost_sample_repeats_the_trial_then_gives_up_with_the_reason():
    clock, odom, warnings = FakeClock(), OdomLog(), []
    graph = SimGraph(odom, speed=0.2, lose={1})
    trial = SimTrials(GAITS, graph, odom, _waiter(clock), TrialTiming(5.0, 10.0), warnings.append)
    assert trial(3).speed == pytest.approx(0.2) and graph.attempt == 2
    assert 'repeating the trial (attempt 2)' in warnings[0]
    graph = SimGraph(odom := OdomLog(), speed=0.2, lose={1, 2, 3})
    trial = SimTrials(GAITS, graph, odom, _waiter(clock), TrialTiming(5.0, 10.0), warnings.append)
    with pytest.raises(TrialAborted, match='kept getting lost'):
        trial(3)


def test_a_sim_trial_ignores_the_tipped_sample_stamped_at_its_reset():
    # sim_node publishes the scheduled sample of the reset's step (the last trial's robot, on
    # its back) and then the pose at the origin, both with the reset's stamp (seen in CI: the
    # trial after a tipped one was stopped as tipped 70 ms in)
    clock, odom = FakeClock(), OdomLog()
    graph = SimGraph(odom, speed=0.2)
    reset = graph.reset

    def reset_after_a_tip():
        odom.append(OdomSample(graph.now, 0.5, 0, 0, 0, 0.0, upside_down=True, tilt=3.0))
        return reset()

    graph.reset = reset_after_a_tip
    trial = SimTrials(
        GAITS, graph, odom, _waiter(clock), TrialTiming(5.0, 10.0), print, tip_guard=1.0
    )
    walked = trial(2)
    assert not walked.tipped and walked.speed == pytest.approx(0.2) and walked.peak_tilt == 0.0


def test_a_refused_reset_and_a_silent_simulator_abort_with_what_happened():
    clock, odom = FakeClock(), OdomLog()
    graph = SimGraph(odom, speed=0.2)
    graph.refuse_reset = 'engine busy'
    trial = SimTrials(GAITS, graph, odom, _waiter(clock), TrialTiming(5.0, 10.0), print)
    with pytest.raises(TrialAborted, match='refused the reset: engine busy'):
        trial(1)
    graph.refuse_reset = ''
    graph.publish_gait = lambda gait: (999, 0.0)  # published, but sim_node never plays it
    with pytest.raises(TrialAborted, match='timed out after 10 s waiting for sim_node to play'):
        trial(1)


class Arriving(SampleLog):
    """Trial results that arrive when the clock reaches their ``received`` time."""

    def __init__(self, clock: FakeClock) -> None:
        super().__init__()
        self.clock = clock

    def received_after(self, t):
        found = super().received_after(t)
        return found if found is not None and found.received <= self.clock() else None


class Bridge:
    """
    bridge_node as a trial sees it: uploads, starts, then publishes the trial's result.

    ``script`` lists what each walk's result says, in turn: a velocity (walked whole) or a
    ``(retryable, reason)`` fault; the last repeats. ``link`` says why the link is down ('').
    """

    def __init__(self, results, clock: FakeClock, velocity=(0.3, 0.0), crab=0.0, script=None):
        self.results, self.clock, self.crab = results, clock, crab
        self.script = list(script or [velocity])
        self.answer = None
        self.link = ''
        self.starts = self.uploads = self.stops = 0

    def upload(self, gait, timeout):
        self.uploads += 1
        return self.answer or Upload(True, 'uploaded', gait.archive_index), self.crab

    def start_trial(self):
        self.starts += 1
        said = self.script[min(self.starts, len(self.script)) - 1]
        t = self.clock() + 6.0
        if isinstance(said[0], bool):
            retryable, reason = said
            self.results.append(RobotTrialResult(False, retryable, reason, 19.0, 0.0, t))
        else:
            self.results.append(RobotTrialResult(True, False, '', *said, received=t))
        return True, 'started'

    def link_problem(self):
        return self.link

    def stop_trial(self):
        self.stops += 1
        return True, 'stopped'


def _robot(bridge, clock, timing=None, waiter=None, **kw):
    told: list[str] = []
    trial = RobotTrials(
        GAITS,
        bridge,
        bridge.results,
        waiter or _waiter(clock),
        timing or TrialTiming(5.0, 10.0),
        bridge.link_problem,
        told.append,
        MAX_SPEED,
        clock.sleep,
        clock,
        **kw,
    )
    return trial, told


MAX_SPEED = 4.8


def test_a_robot_trial_reads_the_bridge_result_that_follows_its_start():
    clock = FakeClock()
    results = Arriving(clock)
    results.append(RobotTrialResult(True, False, '', 9.0, 9.0, received=-1.0))  # an earlier one
    bridge = Bridge(results, clock, velocity=(0.0, 0.2), crab=math.pi / 2)
    trial, _ = _robot(bridge, clock, TrialTiming(5.0, 10.0, 1.0))
    assert trial(4).speed == pytest.approx(0.2)
    assert clock.t >= 1.0  # stood still first


def test_a_gait_the_robot_refuses_or_confirms_for_another_index_aborts():
    clock = FakeClock()
    bridge = Bridge(Arriving(clock), clock)
    trial, _ = _robot(bridge, clock)
    bridge.answer = Upload(False, 'gait not uploaded: step height out of range', 4)
    with pytest.raises(TrialAborted, match='step height out of range'):
        trial(4)
    bridge.answer = Upload(True, 'uploaded', 5)
    with pytest.raises(TrialAborted, match='did not confirm'):
        trial(4)


def test_a_trial_the_link_spoilt_is_never_scored_and_is_walked_again_once_the_link_is_back():
    clock = FakeClock()
    bridge = Bridge(
        Arriving(clock), clock, script=[(True, 'the radio port was lost'), (0.25, 0.0)]
    )
    bridge.link = 'the radio port is not open'
    trial, told = _robot(bridge, clock)
    back_at = [None]

    def link():  # the link comes back 20 s after the fault
        if back_at[0] is None:
            back_at[0] = clock() + 20.0
        return bridge.link if clock() < back_at[0] else ''

    trial.link = link
    outcome = trial(7)
    assert outcome.speed == pytest.approx(0.25) and not outcome.tipped  # the second walk's
    assert bridge.uploads == bridge.starts == 2  # uploaded again: a restarted robot forgot it
    assert bridge.stops == 1  # the robot stood before: it may still have walked the cut trial
    assert 'not scored: the radio port was lost' in told[0] and '(try 2;' in told[0]
    assert 'waiting up to 60 s' in told[1] and 'radio link back after' in told[2]


def test_a_fault_read_before_the_link_status_sent_ahead_of_it_still_waits_for_the_link():
    # seen in CI: the trial's LINK_LOST result was read before the 'down' link status that
    # bridge_node had sent first; the run took the older 'up' status and uploaded at once
    clock = FakeClock()
    bridge = Bridge(
        Arriving(clock), clock, script=[(True, 'the radio port was lost'), (0.25, 0.0)]
    )

    def fault():  # when the cut trial's result came
        return bridge.results.snapshot()[0].received

    def heard():  # when the newest link status came: 'down' 0.3 s after the result
        return fault() + 0.3 if bridge.starts and clock() >= fault() + 0.3 else 0.0

    def link():  # the older status says up; the 'down' one holds for 20 s
        return 'the radio port is not open' if fault() + 0.3 <= clock() < fault() + 20 else ''

    trial, told = _robot(bridge, clock, link_heard=heard)
    trial.link = link
    assert trial(7).speed == pytest.approx(0.25)
    assert 'waiting up to 60 s' in told[1] and 'radio link back after' in told[2]


def test_a_gait_spoilt_on_every_walk_ends_the_run_with_the_last_reason():
    clock = FakeClock()
    bridge = Bridge(Arriving(clock), clock, script=[(True, 'the robot was silent for 3.2 s')])
    trial, told = _robot(bridge, clock)
    with pytest.raises(
        TrialAborted,
        match=r'not walked and measured whole \(3 walks spoilt, 0 unanswered\); the last: the'
        ' robot was silent for 3.2 s',
    ):
        trial(2)
    assert bridge.starts == 3 and len(told) == 2


def test_a_link_that_does_not_come_back_ends_the_run_naming_the_wait():
    clock = FakeClock()
    bridge = Bridge(Arriving(clock), clock, script=[(True, 'the radio port was lost')])
    bridge.link = 'the radio port is not open (/dev/ttyUSB0 lost)'
    trial, _ = _robot(bridge, clock, link_timeout=30.0)
    with pytest.raises(
        TrialAborted,
        match=r'the radio link did not come back in 30 s: the radio'
        r' port is not open \(/dev/ttyUSB0 lost\)',
    ):
        trial(2)
    assert bridge.starts == 1


def test_an_unanswered_upload_or_start_is_the_links_fault_a_refusal_is_not():
    clock = FakeClock()
    bridge = Bridge(Arriving(clock), clock, velocity=(0.2, 0.0))
    trial, told = _robot(bridge, clock)
    answers = iter([Upload(False, 'gait not uploaded: no answer in 3.0 s', 2, answered=False)])
    bridge.upload = lambda gait, timeout: (
        next(answers, Upload(True, '', gait.archive_index)),
        0.0,
    )
    assert trial(2).speed == pytest.approx(0.2)
    assert 'did not answer the upload' in told[0]
    # a start refused while the link is down is walked again; while it works, it ends the run
    starts = iter([(False, 'robot did not start the trial: no acknowledgement')])
    walk = bridge.start_trial
    bridge.start_trial = lambda: next(starts, None) or walk()
    bridge.link = 'the robot has been silent for 4.0 s'
    back = iter([True, True, False])
    trial.link = lambda: bridge.link if next(back, False) else ''
    assert trial(2).speed == pytest.approx(0.2)
    bridge.start_trial = lambda: (False, 'robot did not start the trial: ESTOPPED')
    trial.link = lambda: ''
    with pytest.raises(TrialAborted, match='bridge_node did not start the trial: .*ESTOPPED'):
        trial(2)


def test_a_speed_faster_than_the_robot_can_walk_is_never_scored():
    clock = FakeClock()
    # what a lost link made up (19.3 m/s), then the walk measured whole
    bridge = Bridge(Arriving(clock), clock, script=[(19.26, 0.0), (0.21, 0.0)])
    trial, told = _robot(bridge, clock)
    assert trial(5).speed == pytest.approx(0.21)
    assert 'faster than the robot can walk (4.80 m/s)' in told[0]


def test_a_trial_stopped_by_someone_else_is_not_walked_again():
    clock = FakeClock()
    bridge = Bridge(
        Arriving(clock), clock, script=[(False, 'the walk was stopped before its end')]
    )
    trial, _ = _robot(bridge, clock)
    with pytest.raises(TrialAborted, match='cannot be scored: the walk was stopped'):
        trial(1)
    assert bridge.starts == 1


def test_a_cancel_ends_any_wait_at_once():
    clock = FakeClock()
    cancel = []
    waiter = Waiter(lambda: True, clock=clock, sleep=clock.sleep, cancelled=lambda: bool(cancel))
    bridge = Bridge(Arriving(clock), clock, script=[(True, 'the radio port was lost')])
    bridge.link = 'the radio port is not open'
    trial, _ = _robot(bridge, clock, waiter=waiter)
    waiter.sleep = lambda dt: (clock.sleep(dt), clock.t > 30.0 and cancel.append(1))
    with pytest.raises(TrialCancelled, match='cancelled while waiting for the radio link'):
        trial(1)
    assert clock.t < 30.1


def _manual(clock, results=None):
    prompts: list[str] = []
    results = results if results is not None else Arriving(clock)
    bridge = Bridge(results, clock, script=[(False, 'no IMU configured')])
    manual = ManualTrials(
        GAITS,
        bridge,
        results,
        _waiter(clock),
        TrialTiming(5.0, 10.0),
        prompts.append,
        clock.sleep,
        clock,
    )
    return manual, bridge, prompts


def test_manual_trials_take_a_plausible_distance_only_once_the_walk_ended():
    clock = FakeClock()
    manual, bridge, prompts = _manual(clock)
    assert manual.report(1.0).startswith('no manual trial is waiting for a distance')

    class Operator(Waiter):
        """The operator measures once the walk ended; not before."""

        def until(self, predicate, timeout, what):
            if 'distance' in what:
                assert manual.report(float('nan')).startswith('distance nan m')
                assert manual.report(51.0).startswith('distance 51.0 m')
                assert manual.report(1.5) == ''
            else:
                assert manual.report(1.0).startswith('no manual trial is waiting')
            return super().until(predicate, timeout, what)

    manual.waiter = Operator(lambda: True, clock=clock, sleep=clock.sleep)
    assert manual(2) == pytest.approx(0.3)
    assert bridge.starts == 1  # the walk was started through bridge_node
    assert 'archive gait 2' in prompts[0] and 'report_distance' in prompts[0]
    assert not manual.waiting


def test_a_manual_trial_reported_as_zero_or_backwards_ends_at_once():
    for distance in (0.0, -0.4):
        clock = FakeClock()
        manual, _bridge, _ = _manual(clock)

        class Operator(Waiter):
            """The operator reports the distance as soon as it is asked for."""

            def until(self, predicate, timeout, what):
                if 'distance' in what:
                    assert manual.report(distance) == ''
                    self.began = clock.t
                return super().until(predicate, timeout, what)

        manual.waiter = Operator(lambda: True, clock=clock, sleep=clock.sleep)
        assert manual(3) == pytest.approx(distance / 5.0)
        assert clock.t - manual.waiter.began < 0.01  # no poll waited for a "truthy" distance


def test_the_waiter_stops_for_a_check_and_on_shutdown():
    clock = FakeClock()
    waiter = _waiter(clock, check=lambda: 'two nodes named /sim_node' if clock.t > 2 else '')
    with pytest.raises(TrialAborted, match='two nodes named'):
        waiter.until(lambda: False, 60.0, 'nothing')
    assert 2.0 < clock.t < 4.0
    alive = iter([True, False])
    waiter = Waiter(lambda: next(alive), clock=clock, sleep=clock.sleep)
    with pytest.raises(TrialAborted, match='shutting down'):
        waiter.until(lambda: False, 60.0, 'nothing')
    assert _waiter(clock).until(lambda: 42, 1.0, 'an answer') == 42


def test_a_gait_that_ends_upside_down_is_a_fall_not_a_walk():
    """
    On PyBullet this gait ends on its back with leg 1 lifted: a fall, scored 0.

    (Frozen in test/data/falling_gaits.json: gait 19326 of the CMA-MAE default map of
    2026-11-25, at friction 1; on the first default map gait 6312 did, sliding 5 m.)
    """
    import json
    from pathlib import Path

    from hexapod_sim.evaluation import FELL_OVER
    from hexapod_sim.simulator import upside_down

    falling = Path(__file__).resolve().parents[1] / 'data' / 'falling_gaits.json'
    genes = json.loads(falling.read_text())['upside_down_leg_1_lifted']['genotype']
    from hexapod_sim import create_simulator, evaluate_gait, SimConfig

    with create_simulator(SimConfig(engine='pybullet')) as s:
        result = evaluate_gait(genes, s, collisions_fatal=False, failed_legs=[1])
        assert upside_down(s.base_pose()[1])  # it did end on its back
        assert result.fitness == 0.0 and result.reason == FELL_OVER and not result.valid
        upright = evaluate_gait(genes, s, collisions_fatal=False, failed_legs=[])
        assert upright.valid and upright.fitness != 0.0
    assert not upside_down((0.0, 0.0, 0.0, 1.0)) and upside_down((1.0, 0.0, 0.0, 0.0))
    assert not upside_down((0.38, 0.0, 0.0, 0.92))  # rolled 45 degrees: still up


def test_a_graph_trial_that_ends_upside_down_measures_0():
    from hexapod_adapt.online.trials import OdomSample, sim_trial_speed

    start = OdomSample(0, 0.0, 0.0, 0.0, 0.0, 0.0)
    walked = OdomSample(5_000_000_000, 1.5, 0.0, 0.0, 0.0, 0.0)
    fell = OdomSample(5_000_000_000, 1.5, 0.0, 0.0, 0.0, 0.0, upside_down=True)
    assert sim_trial_speed([start, walked], 0, 5.0, 0.0) == pytest.approx(0.3)
    assert sim_trial_speed([start, fell], 0, 5.0, 0.0) == 0.0


def test_an_unanswered_upload_between_spoilt_walks_is_not_a_spoilt_walk():
    # 10 s of radio silence: the walk is spoilt by the IMU gap first, then the next upload goes
    # unanswered while the robot is still silent, then the link is back: the gait is walked whole
    clock = FakeClock()
    bridge = Bridge(Arriving(clock), clock, script=[(True, 'no IMU sample for 1.6 s'), (0.2, 0.0)])
    trial, told = _robot(bridge, clock)
    answers = iter([Upload(True, '', 3), Upload(False, 'no answer in 3.0 s', 3, answered=False)])
    bridge.upload = lambda gait, timeout: (
        next(answers, Upload(True, '', gait.archive_index)),
        0.0,
    )
    assert trial(3).speed == pytest.approx(0.2)
    assert len(told) == 2 and '(try 3;' in told[1] and 'did not answer the upload' in told[1]
