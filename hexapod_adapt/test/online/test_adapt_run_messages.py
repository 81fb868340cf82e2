# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""What adapt_node decides around M-BOA, checked without ROS (online.run_messages, run_config)."""

from __future__ import annotations

import math
from pathlib import Path

from hexapod_adapt.mapping.maps import DEMO_MAP, shipped_map
from hexapod_adapt.online import run_messages
from hexapod_adapt.online.adaptation import AdaptationResult
from hexapod_adapt.online.run_config import ArchiveSlot, settings_problem
from hexapod_adapt.online.trials import MODES


def test_sim_trials_walk_what_was_asked_and_robot_trials_what_the_bridge_walks():
    said: list[str] = []
    assert run_messages.trial_walk('sim', 5.0, 1.0, None, said.append) == (5.0, 1.0)
    assert run_messages.trial_walk('robot', 5.0, 0.0, (5.0, 0.5), said.append) == (5.0, 0.5)
    assert not said
    assert run_messages.trial_walk('robot', 3.0, 0.0, (5.0, 0.0), said.append) == (5.0, 0.0)
    assert 'bridge_node walks 5 s timed: its trial_duration is used' in said[-1]
    assert run_messages.trial_walk('manual', 4.0, 0.0, None, said.append) == (4.0, 0.0)
    assert 'assuming 4 s from standing' in said[-1]


def test_a_name_taken_twice_stops_a_run_and_one_does_not():
    assert run_messages.duplicate_problem('/sim_node', 1) == ''
    assert run_messages.duplicate_problem('/sim_node', 0) == ''
    assert run_messages.duplicate_problem('/sim_node', 2).startswith('2 nodes named /sim_node')


def test_a_distance_without_a_manual_trial_is_refused_with_the_reason():
    assert run_messages.report_distance(None, 1.0) == 'no manual trial is waiting for a distance'
    assert 'not a plausible trial distance' in run_messages.report_distance(None, float('nan'))


def test_the_response_says_the_engine_gap_and_a_recording_problem():
    result = AdaptationResult(success=True, message='stopped: alpha reached')
    assert run_messages.result_message(result, '', '') == 'stopped: alpha reached'
    text = run_messages.result_message(result, 'map made on mujoco', 'disk full')
    assert text == 'stopped: alpha reached (map made on mujoco); recording: disk full'
    assert run_messages.veto_message(7, math.radians(41.0), math.radians(30.0)) == (
        'gait 7 skipped: it tilts the body 41 deg in simulation under the damage, past the'
        ' 30 deg tip guard; never tried'
    )
    vetoed = AdaptationResult(success=True, message='stopped: alpha reached', vetoed=[7, 12])
    assert run_messages.result_message(vetoed, '', '') == (
        'stopped: alpha reached; never tried, predicted to tip past the tip guard: gait(s) 7, 12'
    )


def test_a_bad_archive_keeps_the_last_good_one(tmp_path: Path):
    slot = ArchiveSlot('sim', MODES)
    assert slot.load(str(shipped_map(DEMO_MAP))) == ''
    good = slot.archive
    assert good is not None and 'gaits in' in slot.describe()
    broken = tmp_path / 'broken.npz'
    broken.write_bytes(b'not a map')
    problem = slot.load(str(broken))
    assert problem and slot.archive is good and slot.problem == ''


def test_an_unknown_mode_leaves_the_node_without_an_archive_for_good():
    slot = ArchiveSlot('telepathy', MODES)
    assert not slot.usable
    assert 'parameter mode must be one of sim, robot, manual' in slot.load('')
    assert slot.archive is None and slot.describe() == slot.problem


def test_run_settings_are_checked_by_the_request_rules():
    good = {
        'max_trials': 20,
        'trial_duration': 5.0,
        'alpha': 0.9,
        'kappa': 0.05,
        'length_scale': 0.4,
        'noise': 0.001,
        'profile': 'default',
    }
    assert settings_problem(good) == ''
    assert settings_problem({**good, 'trial_duration': -1.0})
    assert settings_problem({**good, 'profile': 'nonsense'})


def test_a_diagnosis_says_what_the_run_goes_on_as_or_that_no_hypothesis_fits():
    from hexapod_adapt.online.diagnosis import Posterior
    import numpy as np

    post = Posterior(
        ('leg 1 lifted', 'leg 2 lifted', 'none of these'), np.array([0.95, 0.04, 0.01])
    )
    say = run_messages.diagnosis_message
    named = say(2, 'leg 1 lifted', post)
    assert named.startswith('diagnosis after trial 2: leg 1 lifted 0.95')
    assert named.endswith('; the run goes on as leg 1 lifted')
    assert say(2, '', post).endswith('; no damage named yet')
    assert say(2, '', post, unfit=True).endswith(
        '; no hypothesis fits the trials: the run goes on blind'
    )
    widened = say(3, 'leg 1 lifted', post, widened=3)
    assert widened.startswith('diagnosis after trial 3 (none of the first bank fits them: every')
    assert 'wider' not in say(4, 'leg 1 lifted', post, widened=3)
    rescoring = say(3, 'leg 1 locked', post, rescoring=True)
    assert rescoring.endswith(
        "; the run goes on as leg 1 locked (no re-score cached: the map's fastest gaits are"
        ' walked under it first)'
    )
    # the action feedback's note of that trial says so too; a cached one says nothing
    assert run_messages.rescore_note('leg 1 locked') == (
        "leg 1 locked named, no re-score cached: the map's fastest gaits are walked under it first"
    )
    assert 'cached' not in named
    # and the run's last line says how long it took
    from hexapod_adapt.online.adaptation import AdaptationResult

    done = AdaptationResult(True, 'gait found', rescore_s=26.6)
    assert run_messages.finish_message(done).endswith(
        '0 trials, no gait walked without tipping: none is left on the robot (re-scoring the'
        ' damage it named took 27 s)'
    )
    assert 're-scoring' not in run_messages.finish_message(AdaptationResult(True, 'gait found'))
