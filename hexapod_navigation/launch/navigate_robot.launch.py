# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
r"""
Walking to goals on the real robot: bridge_node + navigate_node (full ROS 2 Jazzy install).

    ros2 launch hexapod_navigation navigate_robot.launch.py [params_file:=my.yaml] \
        port:=/dev/ttyUSB0 imu_port:=/dev/ttyUSB1 leg_map:='[1, 6, 5, 4, 3, 2]'
    ros2 action send_goal --feedback /navigate hexapod_msgs/action/Navigate \
        "{pose: {header: {frame_id: odom}, pose: {position: {x: 1.5, y: 0.5}}}}"
One bridge trial is one repertoire step (trial_duration in the parameter file, 2 s).
In this workspace without `launch`:
    python scripts/launch.py robot --navigate \
        --params-file hexapod_navigation/config/navigate_robot.yaml
"""

from hexapod_description.launch_actions import (
    BRIDGE,
    configured_node,
    operator_arguments,
    params_file_argument,
    state_publisher,
)
from launch import LaunchDescription

NAVIGATE = {'record_dir': "one MCAP per goal ('' = no recording)"}


def generate_launch_description() -> LaunchDescription:
    return LaunchDescription(
        [
            params_file_argument('hexapod_navigation', 'navigate_robot.yaml'),
            *operator_arguments(BRIDGE | NAVIGATE),
            configured_node('hexapod_bridge', 'bridge_node', BRIDGE),
            configured_node('hexapod_navigation', 'navigate_node', NAVIGATE, {'mode': 'robot'}),
            # the latched robot_description and /tf_static; odom -> base_link: bridge_node
            state_publisher(),
        ]
    )
