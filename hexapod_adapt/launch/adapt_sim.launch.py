# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
r"""
Adaptation on the simulated robot: gait_node + sim_node + adapt_node (full ROS 2 Jazzy install).

    ros2 launch hexapod_adapt adapt_sim.launch.py [params_file:=my.yaml] [archive:=/path/map.npz] \
        failed_legs:='[1]'
    ros2 action send_goal --feedback /adapt hexapod_msgs/action/Adapt "{max_trials: 20}"
In this workspace without `launch`:
    python scripts/launch.py adapt-sim --archive MAP --failed-legs 1 [--params-file YAML]
"""

from hexapod_description.launch_actions import (
    configured_node,
    operator_arguments,
    params_file_argument,
    state_publisher,
)
from launch import LaunchDescription

SIM = {
    'engine': "sim_node's physics engine (the map's: mujoco made the shipped default map)",
    'substeps': "sim_node's physics steps per 240 Hz row (the map's; 0: the engine's default)",
    'failed_legs': "legs (1-6) lifted in the simulator, e.g. '[1]'",
}
ADAPT = {
    'archive': "a map written by generate_map ('' = the shipped default map)",
    'record_dir': "one MCAP per run ('' = no recording)",
}


def generate_launch_description() -> LaunchDescription:
    return LaunchDescription(
        [
            params_file_argument('hexapod_adapt', 'adapt.yaml'),
            *operator_arguments(SIM | ADAPT),
            # one time base: every node but the clock source (sim_node) runs on sim time
            configured_node('hexapod_gait', 'gait_node', (), {'use_sim_time': True}),
            configured_node('hexapod_sim', 'sim_node', SIM),
            configured_node(
                'hexapod_adapt', 'adapt_node', ADAPT, {'mode': 'sim', 'use_sim_time': True}
            ),
            # the leg links on /tf and the latched robot_description (odom -> base_link: sim_node)
            state_publisher(use_sim_time=True),
        ]
    )
