# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
r"""
Real robot: bridge_node on the radio (and optionally an Xsens) port (full ROS 2 Jazzy install).

    ros2 launch hexapod_bridge robot.launch.py [params_file:=my_robot.yaml] port:=/dev/ttyUSB0 \
        imu_port:=/dev/ttyUSB1 leg_map:='[1, 6, 5, 4, 3, 2]'
In this workspace without `launch`: python scripts/launch.py robot --params-file YAML
"""

from hexapod_description.launch_actions import (
    BRIDGE,
    configured_node,
    operator_arguments,
    params_file_argument,
    state_publisher,
)
from launch import LaunchDescription


def generate_launch_description() -> LaunchDescription:
    return LaunchDescription(
        [
            params_file_argument('hexapod_bridge', 'robot.yaml'),
            *operator_arguments(BRIDGE),
            configured_node('hexapod_bridge', 'bridge_node', BRIDGE),
            # the latched robot_description and /tf_static, so recordings replay in 3D; the
            # odom -> base_link transform comes from bridge_node's IMU odometry
            state_publisher(),
        ]
    )
