# Copyright 2026 Hexapod adaptation team
# All rights reserved.
#
# Permission is hereby granted, free of charge, to any person obtaining a copy
# of this software and associated documentation files (the "Software"), to deal
# in the Software without restriction, including without limitation the rights
# to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
# copies of the Software, and to permit persons to whom the Software is
# furnished to do so, subject to the following conditions:
#
# The above copyright notice and this permission notice shall be included in all
# copies or substantial portions of the Software.
#
# THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
# IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
# FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
# AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
# LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
# OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
# SOFTWARE.
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
