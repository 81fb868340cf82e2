# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Launch actions the workspace's launch files share (full ROS 2 install: needs ``launch_ros``)."""

from hexapod_description.model import urdf_path
from launch_ros.actions import Node


def state_publisher(use_sim_time: bool = False) -> Node:
    """
    ``robot_state_publisher`` on the hexapod URDF.

    It publishes the latched robot_description, the fixed joints on /tf_static and the leg links
    on /tf from joint_states. odom -> base_link comes from sim_node or bridge_node.
    """
    return Node(
        package='robot_state_publisher',
        executable='robot_state_publisher',
        output='screen',
        parameters=[{'robot_description': urdf_path().read_text(), 'use_sim_time': use_sim_time}],
    )
