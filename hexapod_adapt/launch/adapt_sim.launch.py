# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Adaptation on the simulated robot: gait_node + sim_node + adapt_node (full ROS 2 Jazzy install).

    ros2 launch hexapod_adapt adapt_sim.launch.py [archive:=/path/map.npz] failed_legs:='[1]'
    ros2 service call /adapt hexapod_msgs/srv/Adapt "{max_trials: 20}"
In this workspace without `launch`:
    python scripts/launch.py adapt-sim --archive MAP --failed-legs 1
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
            DeclareLaunchArgument(
                'failed_legs', default_value='[]', description='legs (1-6) failed in the simulator'
            ),
            DeclareLaunchArgument('record_dir', default_value='adaptation_runs'),
            DeclareLaunchArgument(
                'engine',
                default_value='mujoco',
                description="sim_node's physics engine (mujoco made the shipped default map)",
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
                        'real_time_factor': 0.0,
                        'failed_legs': LaunchConfiguration('failed_legs'),
                        'engine': LaunchConfiguration('engine'),
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
                        'mode': 'sim',
                        'use_sim_time': True,
                        'record_dir': LaunchConfiguration('record_dir'),
                    }
                ],
            ),
            # the leg links on /tf and the latched robot_description (odom -> base_link: sim_node)
            state_publisher(use_sim_time=True),
        ]
    )
