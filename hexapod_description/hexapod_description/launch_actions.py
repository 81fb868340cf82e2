# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Launch actions the workspace's launch files share (full ROS 2 install: needs ``launch_ros``).

Every launch file takes ``params_file`` (default: a file in its package's ``config/``) and
exposes what an operator sets as launch arguments that default to ``''``: an argument left
empty leaves the parameter file's value (or the node's default); one given takes precedence.
"""

from __future__ import annotations

from typing import Any, Mapping, Sequence

from hexapod_description.model import robot_description_path
from launch.actions import DeclareLaunchArgument, OpaqueFunction
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare
import yaml

#: What an operator sets on bridge_node (the robot launch files' arguments).
BRIDGE = {
    'port': "the 433 MHz radio's serial port",
    'imu_port': "the Xsens IMU's serial port ('' = attitude from telemetry)",
    'firmware': 'v2 (gait upload) | legacy',
    'leg_map': "the robot's leg number of URDF legs 1..6, e.g. '[1, 6, 5, 4, 3, 2]'",
}


def params_file_argument(package: str, file: str) -> DeclareLaunchArgument:
    """``params_file``, by default ``share/<package>/config/<file>``."""
    return DeclareLaunchArgument(
        'params_file',
        default_value=[FindPackageShare(package), f'/config/{file}'],
        description='a ros__parameters YAML file for the nodes started (config/*.yaml)',
    )


def operator_arguments(described: Mapping[str, str]) -> list[DeclareLaunchArgument]:
    """One argument per name (default '': the parameter file's value), with its description."""
    return [
        DeclareLaunchArgument(name, default_value='', description=f'{text} (default: params_file)')
        for name, text in described.items()
    ]


def configured_node(
    package: str,
    executable: str,
    arguments: Sequence[str] = (),
    fixed: Mapping[str, Any] | None = None,
) -> OpaqueFunction:
    """
    Start a node with ``params_file``, then the launch ``arguments`` given, then ``fixed``.

    Each later source takes precedence. An argument's text is read as YAML (``'[1, 4]'`` is a
    list, ``0.0`` a float), as ``ros2 launch`` reads a parameter; an empty one is left out.
    """

    def build(context) -> list[Node]:
        given: dict[str, Any] = {}
        for name in arguments:
            text = LaunchConfiguration(name).perform(context)
            if text != '':
                given[name] = yaml.safe_load(text)
        return [
            Node(
                package=package,
                executable=executable,
                output='screen',
                parameters=[
                    LaunchConfiguration('params_file').perform(context),
                    given,
                    fixed or {},
                ],
            )
        ]

    return OpaqueFunction(function=build)


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
        parameters=[
            {
                'robot_description': robot_description_path().read_text(),
                'use_sim_time': use_sim_time,
            }
        ],
    )
