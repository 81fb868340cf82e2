# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Real robot: bridge_node on the radio (and optionally an Xsens) port (full ROS 2 Jazzy install).

    ros2 launch hexapod_bridge robot.launch.py port:=/dev/ttyUSB0 imu_port:=/dev/ttyUSB1
In this workspace without `launch`: python scripts/launch.py robot --port /dev/ttyUSB0
"""

from hexapod_description.launch_actions import state_publisher
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description() -> LaunchDescription:
    return LaunchDescription(
        [
            DeclareLaunchArgument('port', default_value='/dev/ttyUSB0'),
            DeclareLaunchArgument('imu_port', default_value=''),
            DeclareLaunchArgument('firmware', default_value='v2'),
            Node(
                package='hexapod_bridge',
                executable='bridge_node',
                output='screen',
                parameters=[
                    {
                        'port': LaunchConfiguration('port'),
                        'imu_port': LaunchConfiguration('imu_port'),
                        'firmware': LaunchConfiguration('firmware'),
                    }
                ],
            ),
            # the latched robot_description and /tf_static, so recordings replay in 3D; the
            # odom -> base_link transform comes from bridge_node's IMU odometry
            state_publisher(),
        ]
    )
