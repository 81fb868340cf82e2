# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
r"""
Adaptation on the real robot: bridge_node + adapt_node (full ROS 2 Jazzy install).

    ros2 launch hexapod_adapt adapt_robot.launch.py [params_file:=my.yaml] [archive:=map.npz] \
        port:=/dev/ttyUSB0 imu_port:=/dev/ttyUSB1 leg_map:='[1, 6, 5, 4, 3, 2]'
    ... mode:=manual     # no IMU: report tape-measured distances with
                         # ros2 service call /adapt_node/report_distance ...
bridge_node comes up active (armed) with the shipped file (autostart, arm_on_start); it is a
lifecycle node: ros2 lifecycle set /bridge_node deactivate stops the robot and disarms.
In this workspace without `launch`:
    python scripts/launch.py robot --archive [MAP] \
        --params-file hexapod_adapt/config/adapt_robot.yaml
"""

from hexapod_description.launch_actions import (
    BRIDGE,
    configured_node,
    operator_arguments,
    params_file_argument,
    state_publisher,
)
from launch import LaunchDescription

ADAPT = {
    'archive': "a map written by generate_map ('' = the shipped default map)",
    'mode': 'robot (IMU odometry) | manual (tape-measured distances)',
    'record_dir': "one MCAP per run ('' = no recording)",
}


def generate_launch_description() -> LaunchDescription:
    return LaunchDescription(
        [
            params_file_argument('hexapod_adapt', 'adapt_robot.yaml'),
            *operator_arguments(BRIDGE | ADAPT),
            configured_node('hexapod_bridge', 'bridge_node', BRIDGE),
            configured_node('hexapod_adapt', 'adapt_node', ADAPT),
            # the latched robot_description and /tf_static, so recordings replay in 3D; the
            # odom -> base_link transform comes from bridge_node's IMU odometry
            state_publisher(),
        ]
    )
