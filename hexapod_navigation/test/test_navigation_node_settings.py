# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""navigate_node's settings and refusals, checked without ROS (node_settings, load_navigation)."""

from __future__ import annotations

import math
from pathlib import Path

from hexapod_navigation.core.loading import load_navigation
from hexapod_navigation.core.repertoire import shipped_repertoire
from hexapod_navigation.core.step_bank import shipped_step_bank
from hexapod_navigation.ros import node_settings as settings
import pytest

DEFAULTS = {s.name: s.default for s in settings.SETTINGS}


def test_every_setting_is_read_only_and_the_defaults_make_the_default_config():
    assert all(s.read_only for s in settings.SETTINGS)
    assert settings.node_problem(DEFAULTS) == ''
    config = settings.navigation_config(DEFAULTS)
    assert config.arena is None and config.learn
    assert settings.navigation_config({**DEFAULTS, 'arena': 3.0}).arena == 3.0


def test_a_bad_mode_or_pose_type_is_named():
    assert 'parameter mode must be one of sim, robot' in settings.node_problem(
        {**DEFAULTS, 'mode': 'fly'}
    )
    assert 'pose_type must be pose or odometry' in settings.node_problem(
        {**DEFAULTS, 'pose_type': 'gps'}
    )


@pytest.mark.parametrize('tolerance,time_limit', [(-1.0, 0.0), (0.0, math.inf), (math.nan, 1.0)])
def test_a_goal_with_a_nonsensical_tolerance_or_time_limit_is_refused(tolerance, time_limit):
    problem = settings.goal_settings_problem(tolerance, time_limit)
    assert 'must be 0 (the default) or a positive number' in problem


def test_a_goal_overrides_the_tolerance_and_time_limit_only_when_it_sets_them():
    config = settings.navigation_config(DEFAULTS)
    assert settings.goal_config(config, 0.0, 0.0) == config
    changed = settings.goal_config(config, 0.3, 20.0)
    assert (changed.tolerance, changed.time_limit) == (0.3, 20.0)
    assert changed.optimism == config.optimism


def test_a_bridge_that_walks_other_trials_is_refused():
    assert settings.bridge_trial_problem(None, 2.0) == ''
    assert settings.bridge_trial_problem((2.0, 0.0), 2.0) == ''
    assert 'bridge_node walks 5 s per trial' in settings.bridge_trial_problem((5.0, 0.0), 2.0)
    assert 'settles 1 s' in settings.bridge_trial_problem((2.0, 1.0), 2.0)


def test_the_shipped_repertoire_and_its_bank_load_and_a_missing_file_is_said(tmp_path: Path):
    data = load_navigation(shipped_repertoire(), shipped_step_bank())
    assert data.repertoire is not None and data.bank is not None
    assert data.problem == '' and data.no_bank == ''
    missing = load_navigation(tmp_path / 'none.npz', shipped_step_bank())
    assert missing.repertoire is None and missing.problem.startswith('no navigation repertoire')
    no_bank = load_navigation(shipped_repertoire(), tmp_path / 'none.npz')
    assert no_bank.bank is None and 'no step bank at' in no_bank.no_bank
