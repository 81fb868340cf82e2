# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Publish the hexapod's TF tree and robot_description from its URDF.

For a full ROS 2 Jazzy install; joint angles come from joint_states: sim_node or bridge_node).
Without robot_state_publisher, ``ros2 run hexapod_gait state_publisher`` does the same.

    ros2 launch hexapod_description display.launch.py
"""

from hexapod_description.launch_actions import state_publisher
from launch import LaunchDescription


def generate_launch_description() -> LaunchDescription:
    return LaunchDescription(
        [
            state_publisher(),
        ]
    )
