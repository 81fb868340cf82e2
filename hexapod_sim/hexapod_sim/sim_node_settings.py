# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""sim_node's parameters: each with its default, what it means (units) and its range."""

from __future__ import annotations

from hexapod_sim.simulator import FRICTION
from hexapod_util.ros_glue import ParamSpec
from rclpy.parameter import Parameter

PARAMETERS = (
    ParamSpec(
        'real_time_factor',
        1.0,
        'Simulated seconds per wall-clock second; 0 = as fast as possible',
        range=(0.0, 100.0),
    ),
    ParamSpec(
        'engine',
        'pybullet',
        "Physics engine: 'pybullet' (the thesis's, the reference), 'mujoco' (fast) or 'dart'"
        ' (the judge of maps)',
        read_only=True,
    ),
    ParamSpec('gui', False, 'Open the PyBullet GUI window (engine pybullet only)', read_only=True),
    ParamSpec(
        'friction',
        Parameter.Type.DOUBLE,
        f'Friction coefficient where a foot meets the floor, every engine (unset = {FRICTION:g})',
        read_only=True,
        range=(0.0, 10.0),
    ),
    ParamSpec(
        'substeps',
        0,
        "Physics steps per 240 Hz row, the row's target held through them (0: the engine's"
        ' default). A map made at N steps per row (its fingerprint says: the default map is'
        ' MuJoCo at 4) walks here as it did in the map at N; studies/engines/README.md, "Where the'
        ' engines differ", item 6, gives each engine\'s converged step.',
        read_only=True,
        range=(0, 64),
    ),
    ParamSpec(
        'failed_legs',
        Parameter.Type.INTEGER_ARRAY,
        'Legs (1..6, at most two) failed at start-up',
        read_only=True,
    ),
    ParamSpec(
        'publish_period_steps',
        0,
        'Publish joint_states/odom/imu/foot_contacts every N physics steps (1/240 s each). 0:'
        ' automatic, 24 (10 Hz of sim time) if real_time_factor starts at 0, where the node runs'
        ' ~18x real time and Python readers of 60 Hz fell behind, else 4 (60 Hz). Trials read'
        ' odometry at reset + N steps exactly.',
        read_only=True,
        range=(0, 240),
    ),
    ParamSpec(
        'clock_period_steps',
        6,
        'Publish /clock every N physics steps (6: 40 Hz of sim time) and with every state'
        ' message. Each /clock message wakes every node on use_sim_time: at every step (240 Hz)'
        " a Python node's multi-threaded executor took a whole core (studies/engines/README.md).",
        read_only=True,
        range=(1, 240),
    ),
    ParamSpec('odom_frame', 'odom', 'REP 105 odometry frame', read_only=True),
    ParamSpec('base_frame', 'base_link', 'Robot base frame', read_only=True),
)
