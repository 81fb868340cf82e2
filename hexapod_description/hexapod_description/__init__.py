# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The UCT RARL hexapod's URDF and a small API to read it (ROS-free)."""

from hexapod_description.model import (
    HexapodModel,
    JointLimit,
    LegMount,
    load_model,
    N_LEGS,
    parse_model,
    robot_description_path,
    summary,
    urdf_path,
)

__all__ = [
    'HexapodModel',
    'JointLimit',
    'LegMount',
    'N_LEGS',
    'load_model',
    'parse_model',
    'summary',
    'robot_description_path',
    'urdf_path',
]
