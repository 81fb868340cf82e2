# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Walking to goals on the simulated robot: gait_node + sim_node + navigate_node (full install).

    ros2 launch hexapod_navigation navigate_sim.launch.py failed_legs:='[1, 2]'
    ros2 action send_goal /navigate hexapod_msgs/action/Navigate "{x: 1.5, y: 0.5}" --feedback
In this workspace without `launch`:
    python scripts/launch.py navigate-sim --failed-legs 1 2
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
                'failed_legs', default_value='[]', description='legs (1-6) failed in the simulator'
            ),
            DeclareLaunchArgument(
                'record_dir', default_value='', description="record each goal here ('' = none)"
            ),
            # one time base: every node but the clock source (sim_node) runs on sim time
            Node(
                package='hexapod_gait',
                executable='gait_node',
                output='screen',
                parameters=[{'initial_preset': '', 'use_sim_time': True}],
            ),
            Node(
                package='hexapod_sim',
                executable='sim_node',
                output='screen',
                parameters=[
                    {
                        'engine': 'mujoco',  # the engine that made the shipped repertoire
                        'failed_legs': LaunchConfiguration('failed_legs'),
                    }
                ],
            ),
            state_publisher(use_sim_time=True),
            Node(
                package='hexapod_navigation',
                executable='navigate_node',
                output='screen',
                parameters=[
                    {
                        'mode': 'sim',
                        'record_dir': LaunchConfiguration('record_dir'),
                        'use_sim_time': True,
                    }
                ],
            ),
        ]
    )
