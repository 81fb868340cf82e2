# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The hexapod simulator, gait evaluation and failure scenarios (ROS-free).

One simulator interface, three engines: PyBullet, MuJoCo and DART (the judge).
"""

from hexapod_sim.evaluation import (
    evaluate_gait,
    evaluate_gaits,
    EvaluationResult,
    FAILURE_FITNESS,
    TRIAL_DURATION,
)
from hexapod_sim.physics.engines import create_simulator
from hexapod_sim.scenarios import all_scenarios, scenario, SCENARIO_NAMES
from hexapod_sim.simulator import (
    ENGINES,
    FAILURE_POSE,
    JointRows,
    PlayResult,
    SimConfig,
    Simulator,
    StepReport,
    validate_engine,
    validate_failed_legs,
)

__all__ = [
    'ENGINES',
    'FAILURE_FITNESS',
    'FAILURE_POSE',
    'SCENARIO_NAMES',
    'TRIAL_DURATION',
    'EvaluationResult',
    'JointRows',
    'PlayResult',
    'SimConfig',
    'Simulator',
    'StepReport',
    'all_scenarios',
    'create_simulator',
    'evaluate_gait',
    'evaluate_gaits',
    'scenario',
    'validate_engine',
    'validate_failed_legs',
]
