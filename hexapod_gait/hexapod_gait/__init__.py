"""The 32-parameter kinematic gait controller of the thesis (section 3.4); ROS-free."""
from hexapod_gait.kinematics import LegKinematics, default_kinematics
from hexapod_gait.parameters import (
    DEFAULT_CRAB_ANGLE,
    DEFAULT_PERIOD,
    GENOTYPE_MAPPING_VERSION,
    GENOTYPE_SIZE,
    RANGES,
    GaitParameterError,
    GaitParameters,
    from_genotype,
    to_genotype,
)
from hexapod_gait.presets import PRESETS, preset
from hexapod_gait.trajectory import (
    ROBOT_RATE,
    SIM_RATE,
    JointTable,
    ReachabilityError,
    build_joint_table,
    foot_trajectory,
    key_points,
    stance_mask,
)

__all__ = [
    "DEFAULT_CRAB_ANGLE", "DEFAULT_PERIOD", "GENOTYPE_MAPPING_VERSION", "GENOTYPE_SIZE",
    "GaitParameterError", "GaitParameters", "JointTable", "RANGES", "LegKinematics", "PRESETS",
    "ROBOT_RATE", "ReachabilityError", "SIM_RATE", "build_joint_table", "default_kinematics",
    "foot_trajectory", "from_genotype", "key_points", "preset", "stance_mask", "to_genotype",
]
