# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The 32-parameter kinematic gait controller of the thesis (section 3.4); ROS-free."""

from hexapod_gait.kinematics import default_kinematics, LegKinematics
from hexapod_gait.parameters import (
    DEFAULT_CRAB_ANGLE,
    DEFAULT_PERIOD,
    from_genotype,
    GaitParameterError,
    GaitParameters,
    GENOTYPE_MAPPING_VERSION,
    GENOTYPE_SIZE,
    RANGES,
    to_genotype,
)
from hexapod_gait.presets import preset, PRESETS, standing_gait
from hexapod_gait.trajectory import (
    build_joint_table,
    foot_trajectory,
    JointTable,
    key_points,
    ReachabilityError,
    ROBOT_RATE,
    SIM_RATE,
    stance_mask,
)

__all__ = [
    'DEFAULT_CRAB_ANGLE',
    'DEFAULT_PERIOD',
    'GENOTYPE_MAPPING_VERSION',
    'GENOTYPE_SIZE',
    'GaitParameterError',
    'GaitParameters',
    'JointTable',
    'RANGES',
    'LegKinematics',
    'PRESETS',
    'ROBOT_RATE',
    'ReachabilityError',
    'SIM_RATE',
    'build_joint_table',
    'default_kinematics',
    'foot_trajectory',
    'from_genotype',
    'key_points',
    'preset',
    'standing_gait',
    'stance_mask',
    'to_genotype',
]
