# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
What navigate_node is configured by, and the checks it makes, without ROS.

Its parameters (each read once, at start-up: all read-only), the navigator's settings built from
them, and the reasons a goal or a bridge is refused.
"""

from __future__ import annotations

from dataclasses import asdict, fields
import math
from typing import Any, Mapping

from hexapod_adapt import Setting
from hexapod_navigation.core.config import NavigationConfig

MODES = ('sim', 'robot')
POSE_TYPES = ('pose', 'odometry')
_DEFAULTS = NavigationConfig()
#: NavigationConfig's fields that are node parameters (the GP's settings and the limits).
CONFIG_PARAMS = tuple(f.name for f in fields(NavigationConfig) if f.name not in ('arena', 'learn'))

#: navigate_node's parameters. The node reads every one once, at start-up: all are read-only, so
#: that setting one at run time is refused instead of silently doing nothing.
SETTINGS = (
    Setting('mode', 'sim', 'sim (gait_node + sim_node) or robot (bridge_node)', read_only=True),
    Setting(
        'repertoire',
        '',
        'navigation repertoire file (.npz); empty = the shipped one',
        read_only=True,
    ),
    Setting(
        'bank_file',
        '',
        "the repertoire's damage bank (hexapod_navigation.core.step_bank), weighed when use_bank"
        ' is'
        ' true; empty = the shipped one (it fits the shipped repertoire only)',
        read_only=True,
    ),
    Setting(
        'specialists_file',
        '',
        "gaits made for the bank's damages (hexapod_navigation.core.specialists), used when"
        ' specialists is true; empty = the shipped ones (they fit the shipped bank only)',
        read_only=True,
    ),
    Setting('pose_topic', '', 'external pose source; empty = odom', read_only=True),
    Setting(
        'pose_type',
        'pose',
        "the pose topic's type: pose (PoseStamped) or odometry",
        read_only=True,
    ),
    Setting('sim_node', 'sim_node', 'name of the simulator node', read_only=True),
    Setting('bridge_node', 'bridge_node', 'name of the bridge node', read_only=True),
    Setting('trial_duration', 2.0, "robot mode: bridge_node's trial_duration [s]", read_only=True),
    Setting(
        'arena', 0.0, 'half-width of the square arena around odom [m]; 0 = none', read_only=True
    ),
    Setting(
        'learn',
        True,
        'learn the damage while walking (false: the repertoire as measured)',
        read_only=True,
    ),
    Setting(
        'timeout',
        10.0,
        'longest wait for the graph to answer [s]',
        read_only=True,
        range=(0.1, 600.0),
    ),
    Setting(
        'record_dir',
        '',
        'record each goal to an MCAP file here (a relative path lies under ROS_HOME, ~/.ros);'
        ' empty = no recording',
        read_only=True,
    ),
    *(
        # each of the type of its default (min_stance_legs is a whole number)
        Setting(name, getattr(_DEFAULTS, name), f'NavigationConfig.{name}', read_only=True)
        for name in CONFIG_PARAMS
    ),
)


def node_problem(values: Mapping[str, Any]) -> str:
    """Return why the node's parameter values cannot be used ('' if they can)."""
    if values['mode'] not in MODES:
        return f'parameter mode must be one of {", ".join(MODES)}, got {values["mode"]!r}'
    if values['pose_type'] not in POSE_TYPES:
        return f'parameter pose_type must be pose or odometry, got {values["pose_type"]!r}'
    return ''


def navigation_config(values: Mapping[str, Any]) -> NavigationConfig:
    """Return the navigator's settings from the node's parameters (ValueError names a bad one)."""
    arena = values['arena']
    return NavigationConfig(
        **{name: values[name] for name in CONFIG_PARAMS},
        arena=arena if arena > 0 else None,
        learn=values['learn'],
    )


def goal_settings_problem(tolerance: float, time_limit: float) -> str:
    """Return why a goal's tolerance [m] or time limit [s] is refused ('' if both are fine)."""
    for name, value in (('tolerance', tolerance), ('time_limit', time_limit)):
        if not math.isfinite(value) or value < 0:
            return f'{name} must be 0 (the default) or a positive number, got {value}'
    return ''


def goal_config(config: NavigationConfig, tolerance: float, time_limit: float) -> NavigationConfig:
    """Return ``config`` with a goal's tolerance and time limit (0: the node's own)."""
    return NavigationConfig(
        **{
            **asdict(config),
            'tolerance': tolerance or config.tolerance,
            'time_limit': time_limit or config.time_limit,
        }
    )


def bridge_trial_problem(bridge: tuple[float, float] | None, trial_duration: float) -> str:
    """
    Robot mode: why bridge_node's trials (duration, settling) do not fit the node's steps.

    '' when they fit, or when the bridge did not answer (the upload then says why).
    """
    if bridge is None:
        return ''
    duration, settle = bridge
    if abs(duration - trial_duration) > 1e-6:
        return (
            f'bridge_node walks {duration:g} s per trial but navigate_node steps are'
            f' {trial_duration:g} s: set both trial_duration parameters alike'
        )
    if settle > 0:
        return (
            f'bridge_node settles {settle:g} s before it times a trial, but navigate_node'
            " steps are walks from standing: set bridge_node's trial_settle to 0"
        )
    return ''
