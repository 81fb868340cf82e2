# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Adaptation on the real robot: bridge_node + adapt_node (full ROS 2 Jazzy install).

    ros2 launch hexapod_adapt adapt_robot.launch.py [archive:=/path/map.npz] port:=/dev/ttyUSB0 \
        imu_port:=/dev/ttyUSB1            # mode robot: trial speeds from the IMU estimate
    ... mode:=manual                      # no IMU: report tape-measured distances with
                                          # ros2 service call /adapt_node/report_distance ...
Arm the bridge first: ros2 service call /bridge_node/arm std_srvs/srv/SetBool "{data: true}"
"""

from hexapod_description.launch_actions import state_publisher
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description() -> LaunchDescription:
    return LaunchDescription(
        [
            DeclareLaunchArgument(
                'archive',
                default_value='',
                description="archive file written by generate_map ('' = the shipped default map)",
            ),
            DeclareLaunchArgument('port', default_value='/dev/ttyUSB0'),
            DeclareLaunchArgument('imu_port', default_value=''),
            DeclareLaunchArgument(
                'mode', default_value='robot', description='robot (IMU odometry) or manual'
            ),
            Node(
                package='hexapod_bridge',
                executable='bridge_node',
                output='screen',
                parameters=[
                    {
                        'port': LaunchConfiguration('port'),
                        'imu_port': LaunchConfiguration('imu_port'),
                    }
                ],
            ),
            Node(
                package='hexapod_adapt',
                executable='adapt_node',
                output='screen',
                parameters=[
                    {
                        'archive': LaunchConfiguration('archive'),
                        'mode': LaunchConfiguration('mode'),
                    }
                ],
            ),
            # the latched robot_description and /tf_static, so recordings replay in 3D; the
            # odom -> base_link transform comes from bridge_node's IMU odometry
            state_publisher(),
        ]
    )
