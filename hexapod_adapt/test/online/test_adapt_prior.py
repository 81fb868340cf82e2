# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The damage-informed prior: what the node is told of the damage, and the re-scored map."""

from __future__ import annotations

from dataclasses import replace
import re

from hexapod_adapt.mapping.archive import Archive, load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
from hexapod_adapt.online.ceiling import compute_ceiling
from hexapod_adapt.online.mboa import MboaConfig, PROFILES
from hexapod_adapt.online.prior import (
    damage_prior,
    KnownDamage,
    requested_damage,
    servo_report_verdict,
)
from hexapod_adapt.online.replay import lookup_trial
from hexapod_adapt.online.session import adapt, SessionStart
from hexapod_sim.damage import Damage, damage_from_lists, DAMAGE_KINDS, parse_damage
from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
import pytest


def test_servo_reports_make_a_damage_and_nonsense_is_refused_saying_why():
    known = KnownDamage()
    assert known.for_run(None, False) == (None, 'the map as it is (no damage known)')
    assert 'names no leg' in known.from_servo(40, 0, 'femur')
    assert 'names no leg' in known.from_servo(40, 7, 'femur')
    assert 'names no joint' in known.from_servo(3, 1, 'knee')
    assert known.servo_damage() is None  # nothing taken
    assert known.from_servo(3, 1, 'femur') == 'servo 3 reported dead: leg 1 femur unpowered'
    assert 'already known' in known.from_servo(3, 1, 'femur')
    assert known.from_servo(4, 1, 'tibia') == 'servo 4 reported dead: leg 1 tibia unpowered'
    assert known.from_servo(11, 4, 'coxa') == 'servo 11 reported dead: leg 4 coxa unpowered'
    # a dead servo is a free joint, the live ones fold the leg: not "leg lifted"
    damage, source = known.for_run(None, False)
    assert damage == parse_damage('1:unpowered:femur+tibia,4:unpowered:coxa')
    assert source == 'servo reports: leg 1 unpowered femur+tibia, leg 4 unpowered coxa'
    refusal = known.from_servo(8, 3, 'femur')
    assert 'name 3 failed legs ([1, 3, 4])' in refusal and 'at most 2' in refusal
    damage, source = known.for_run(None, False)
    assert damage is None and 'name 3 failed legs' in source
    # the operator's word still works, and blind means blind
    assert known.for_run(requested_damage([2]), False)[0] == Damage.lifted([2])
    named = requested_damage([2], ['unpowered'], [], ['femur'])
    assert known.for_run(named, False) == (named, 'the request: leg 2 unpowered femur')
    assert known.for_run(named, True) == (None, 'the map as it is (blind prior requested)')


def test_a_request_names_any_damage_and_nonsense_is_refused_saying_why():
    assert requested_damage([]) is None  # the node's own knowledge
    assert requested_damage([1, 4]) == Damage.lifted([1, 4])  # kinds empty: the thesis's
    assert requested_damage([3, 5], ['locked', 'weak'], [0, 0.5]) == parse_damage(
        '3:locked,5:weak:0.5'
    )
    assert requested_damage([2], ['shortened'], [0.0]) == parse_damage('2:shortened')
    assert requested_damage([6], ['unpowered'], [], ['coxa+tibia']) == parse_damage(
        '6:unpowered:coxa+tibia'
    )
    refused = {
        'at most 2 legs': ([1, 2, 3], [], [], []),
        'leg 9 does not exist': ([9], [], [], []),
        "unknown damage kind 'melted'": ([2], ['melted'], [], []),
        '1 damage kinds for 2 legs': ([1, 2], ['locked'], [], []),
        "got ['knee'] for leg 2": ([2], ['unpowered'], [], ['knee']),
        'only an unpowered leg has dead joints': ([2], ['locked'], [], ['femur']),
        'strength in [': ([2], ['weak'], [3.0], []),
        'kinds and joints given without failed_legs': ([], ['unpowered'], [], ['femur']),
    }
    for message, lists in refused.items():
        with pytest.raises(ValueError, match=re.escape(message)):
            requested_damage(*lists)


def test_only_what_the_bridge_confirms_is_believed_and_forget_drops_the_reports():
    bridge = '/bridge_node'
    assert servo_report_verdict(6, True, bridge, []) == ''
    assert servo_report_verdict(6, True, bridge, ['/other']) == ''  # true, whoever sent it
    denied = servo_report_verdict(6, False, bridge, ['/not_the_bridge', '/not_the_bridge'])
    assert 'does not hold servo 6 dead' in denied and denied.endswith(
        'since the last report: /not_the_bridge'
    )
    assert 'the sender left at once' in servo_report_verdict(6, False, bridge, [])
    assert 'did not answer whether servo 6' in servo_report_verdict(6, None, bridge, [])
    known = KnownDamage()
    assert known.from_servo(12, 4, 'femur') == 'servo 12 reported dead: leg 4 femur unpowered'
    assert known.servo_damage() is not None
    assert 'forgot the reports of dead servos [12]' in known.forget()
    assert known.servo_damage() is None and known.forget() == 'no servo reports to forget'
    assert known.for_run(None, False)[1] == 'the map as it is (no damage known)'


def test_one_dead_servo_a_leg_in_any_s1_s4_case_has_a_shipped_ceiling():
    """The bridge's reports on S1-S4 legs need no re-score: the default map's cache has them."""
    from hexapod_adapt.mapping.maps import shipped_ceilings
    from hexapod_adapt.online.ceiling import cached_ceiling
    from hexapod_sim.scenarios import scenario

    archive = load_archive(shipped_map(DEFAULT_MAP))
    for name in ('S1', 'S2', 'S3', 'S4'):
        for legs in scenario(name):
            for joint in ('coxa', 'femur', 'tibia'):
                known = KnownDamage()
                for leg in legs:
                    known.from_servo(100 + leg, leg, joint)  # the servo id plays no part
                damage = known.servo_damage()
                assert damage is not None
                found = cached_ceiling(archive, damage, 'mujoco', [shipped_ceilings()])
                assert found is not None, f'{damage.label}: no shipped ceiling'
                assert found.damage == damage


def test_every_experiment_kind_has_its_21_s1_s4_ceilings_shipped():
    """make_ceilings.sh's 168 cases (8 kinds x S1-S4) are all in the default map's cache."""
    from hexapod_adapt.mapping.maps import shipped_ceilings
    from hexapod_adapt.online.ceiling import cached_ceiling
    from hexapod_sim.damage import EXPERIMENT_KINDS
    from hexapod_sim.scenarios import scenario

    archive = load_archive(shipped_map(DEFAULT_MAP))
    cache = shipped_ceilings()
    legs_all = [legs for name in ('S1', 'S2', 'S3', 'S4') for legs in scenario(name)]
    assert len(EXPERIMENT_KINDS) * len(legs_all) == 168
    missing = [
        f'{kind} legs {legs}'
        for kind in EXPERIMENT_KINDS
        for legs in legs_all
        if cached_ceiling(archive, Damage.of(kind, legs), 'mujoco', [cache]) is None
    ]
    assert not missing, f'no shipped ceiling for {missing}'


def test_the_simulators_damage_is_taken_and_a_request_that_differs_is_said():
    known = KnownDamage()
    assert known.from_sim([2, 5], ['locked', 'weak'], [1.0, 0.5]).endswith(
        'leg 2 locked, leg 5 weak 0.50'
    )
    damage, source = known.for_run(None, False)
    assert damage.kind_of(5) == 'weak' and source.startswith('the simulator: ')
    damage, source = known.for_run(Damage.lifted([1]), False)
    assert damage == Damage.lifted([1]) and 'note: the simulator reports leg 2 locked' in source
    same = parse_damage('2:locked,5:weak:0.5')
    assert known.for_run(same, False)[1] == 'the request: leg 2 locked, leg 5 weak 0.50'
    assert 'refused' in known.from_sim([1, 2, 3], [], [])
    assert known.sim.failed_legs == (2, 5)  # the refused report changed nothing
    known.from_sim([], [], [])
    no_damage = (None, 'the map as it is (the simulator reports no damage)')
    assert known.for_run(None, False) == no_damage


@pytest.fixture(scope='module')
def tiny_map() -> Archive:
    """30 gaits of the default map (MuJoCo), the fastest first."""
    return _fastest_of_default_map(30)


def _fastest_of_default_map(n: int) -> Archive:
    """Return the default map with only its ``n`` fastest gaits."""
    full = load_archive(shipped_map(DEFAULT_MAP))
    elites = full.elite_indices()
    return full.only(elites[np.argsort(-full.fitness[elites])[:n]])


@pytest.mark.slow
def test_m_boa_starts_from_the_re_scored_map(tiny_map, tmp_path):
    damage = Damage.lifted([4, 5])
    seen = []
    prior = damage_prior(
        tiny_map, damage, 'mujoco', tmp_path, progress=lambda d, t: seen.append((d, t))
    )
    truth = compute_ceiling(tiny_map, damage, 'mujoco')
    np.testing.assert_array_equal(prior.speeds, truth.speeds)
    assert seen[-1] == (30, 30)
    assert 'under legs 4+5 lifted' in prior.describe()
    again = damage_prior(tiny_map, damage, 'mujoco', tmp_path)
    assert 'cached' in again.describe()
    config = MboaConfig(max_trials=5, alpha=1.0)
    informed = adapt(tiny_map, lookup_trial(truth), config, SessionStart(prior.speeds))
    blind = adapt(tiny_map, lookup_trial(truth), config)
    assert informed.niches[0] == truth.best_niche  # same engine: the first trial is the best
    assert informed.best_speed == truth.best_speed
    assert blind.niches[0] == int(
        tiny_map.elite_indices()[np.argmax(tiny_map.speeds()[tiny_map.elite_indices()])]
    )
    with pytest.raises(ValueError, match='one speed per gait'):
        adapt(tiny_map, lookup_trial(truth), config, SessionStart(prior.speeds[:3]))


@pytest.mark.slow
def test_a_streaming_prior_scores_the_best_gaits_first_and_caches_the_whole(tiny_map, tmp_path):
    from hexapod_adapt.online.streaming_prior import StreamingPrior

    damage = Damage.of('unpowered_femur', [2])
    truth = compute_ceiling(tiny_map, damage, 'mujoco')
    stream = StreamingPrior(tiny_map, damage, 'mujoco', tmp_path, workers=1, first=10)
    assert not stream.cached and stream.wait_first(120)
    first = stream.snapshot()
    assert first.scored >= 10 and np.all(np.isfinite(first.speeds))
    # the first scored are the map's best by intact speed, exactly as the ceiling scores them
    intact = tiny_map.speeds()[tiny_map.elite_indices()]
    top = np.argsort(-intact, kind='stable')[:10]
    np.testing.assert_array_equal(first.speeds[top], truth.speeds[top])
    taken = stream.take()  # what the first trial starts from; update() waits for more after it
    stream._thread.join(120)
    if stream.snapshot().scored > taken.scored:
        assert stream.update() is not None  # the rest came
    assert stream.update() is None  # and was taken
    assert stream.snapshot().complete
    np.testing.assert_array_equal(stream.snapshot().speeds, truth.speeds)
    again = StreamingPrior(tiny_map, damage, 'mujoco', tmp_path)
    assert again.cached and again.wait_first(0)  # the whole was cached


@pytest.mark.slow
def test_a_closed_re_score_ends_its_workers_at_once_not_after_their_chunk(tmp_path):
    """Closed, a re-score's workers walked their chunk (64 gaits: seconds) beside the next's."""
    import os
    import time

    from hexapod_adapt.online.streaming_prior import CHUNK, StreamingPrior
    from hexapod_util.processes import child_pids, is_running

    archive = _fastest_of_default_map(2 * CHUNK)
    before = child_pids(os.getpid())
    stream = StreamingPrior(archive, Damage.of('unpowered_femur', [2]), 'mujoco', tmp_path)
    deadline = time.monotonic() + 60
    while not child_pids(os.getpid()) - before and time.monotonic() < deadline:
        time.sleep(0.05)
    workers = child_pids(os.getpid()) - before
    assert workers, 'the re-score started no worker'
    time.sleep(1.0)  # importing the engine, then walking its first chunk: far more than this
    t0 = time.monotonic()
    stream.close()
    stream._thread.join(60)
    took = time.monotonic() - t0
    assert not stream._thread.is_alive()
    assert stream.snapshot().scored == 0 and not stream.error  # closed mid-chunk, quietly
    assert took < 5.0, f'the re-score took {took:.1f} s to stop'
    assert not [pid for pid in workers if is_running(pid)], 'a worker walks on after close()'
    assert not list(tmp_path.iterdir())  # nothing cached


@pytest.mark.slow
def test_a_run_whose_re_score_is_stopped_says_so_and_not_that_it_timed_out(tiny_map, tmp_path):
    """A log on CI once blamed a 600 s timeout on a re-score that the node's shutdown stopped."""
    import threading

    from hexapod_adapt.online.streaming_prior import StreamingPriors

    priors = StreamingPriors(str(tmp_path), [], workers=1, log=lambda _line: None)
    # stopped while the workers still start (they import the engine: seconds)
    threading.Timer(0.2, priors.close).start()
    start = priors.start(tiny_map, Damage.of('unpowered_femur', [2]), 'the request')
    assert start.speeds is None
    assert 'stopped before the top of the map was scored' in start.note, start.note
    assert 'not re-scored in' not in start.note


def test_a_partial_prior_estimates_the_gaits_not_yet_scored_from_those_scored():
    from hexapod_adapt.online.ceiling import estimate_unwalked

    intact = np.array([0.4, 0.3, 0.2, 0.1, 0.0])
    scored = np.array([0.2, 0.3, np.nan, np.nan, np.nan])  # ratios 0.5 and 1.0: median 0.75
    prior = estimate_unwalked(intact, scored)
    np.testing.assert_allclose(prior, [0.2, 0.3, 0.15, 0.075, 0.0])
    assert np.isnan(scored[2])  # the caller's array is left as it was
    np.testing.assert_array_equal(estimate_unwalked(intact, np.full(5, np.nan)), intact)


@pytest.mark.slow
def test_the_expected_gain_stop_is_for_blind_runs_only(tiny_map):
    truth = compute_ceiling(tiny_map, Damage.lifted([1]), 'mujoco')
    config = replace(PROFILES['default'], max_trials=10)
    assert config.stop_gain > 0  # the default profile has one
    informed = adapt(tiny_map, lookup_trial(truth), config, SessionStart(truth.speeds))
    # the known damage's best, tried first, meets alpha: the run ends there
    assert len(informed.trials) == 1 and informed.success
    assert informed.niches[0] == truth.best_niche
    # the same start without the gain stop stops the same way: the stop is alpha's
    plain = replace(config, stop_gain=None)
    again = adapt(tiny_map, lookup_trial(truth), plain, SessionStart(truth.speeds))
    assert again.niches == informed.niches
    # blind, the gain stop keeps the run going while an untried gait may gain 2 mm/s or more
    blind = adapt(tiny_map, lookup_trial(truth), config)
    blind_plain = adapt(tiny_map, lookup_trial(truth), plain)
    assert len(blind.trials) > len(blind_plain.trials)


@pytest.mark.slow
def test_adapt_takes_a_newer_prior_between_trials(tiny_map):
    truth = compute_ceiling(tiny_map, Damage.lifted([1]), 'mujoco')
    config = MboaConfig(max_trials=3, alpha=1.0)
    wrong = truth.speeds.max() - truth.speeds  # the worst gait looks best
    updates = iter([None, truth.speeds])  # the true prior arrives before the second trial
    run = adapt(
        tiny_map,
        lookup_trial(truth),
        config,
        SessionStart(wrong, lambda: next(updates, None)),
    )
    assert run.niches[1] == truth.best_niche  # the second trial follows the newer prior
    assert [t.number for t in run.trials] == list(range(1, len(run.trials) + 1))


@pytest.mark.slow
@settings(max_examples=500, deadline=None)
@given(
    legs=st.lists(st.integers(0, 255), max_size=8),
    kinds=st.lists(st.sampled_from(DAMAGE_KINDS) | st.text(max_size=12), max_size=8),
    strengths=st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=8),
    joints=st.lists(
        st.sampled_from(('', 'femur', 'coxa+tibia')) | st.text(max_size=12), max_size=8
    ),
)
def test_any_request_lists_make_a_damage_or_a_reason(legs, kinds, strengths, joints):
    """A hostile request (the Adapt service's, navigate_node's) is a damage or a ValueError."""
    try:
        damage = requested_damage(legs, kinds, strengths, joints)
    except ValueError as exc:
        assert str(exc)
        return
    if damage is None:
        assert not legs and not kinds and not strengths and not joints
    else:
        assert damage == damage_from_lists(*damage.as_lists())  # the lists round-trip
