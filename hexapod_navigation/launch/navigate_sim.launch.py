# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
r"""
Walking to goals on the simulated robot: gait_node + sim_node + navigate_node (full install).

    ros2 launch hexapod_navigation navigate_sim.launch.py [params_file:=my.yaml] \
        failed_legs:='[1, 2]'
    ros2 action send_goal --feedback /navigate hexapod_msgs/action/Navigate \
        "{pose: {header: {frame_id: odom}, pose: {position: {x: 1.5, y: 0.5}}}}"
In this workspace without `launch`:
    python scripts/launch.py navigate-sim --failed-legs 1 2 [--params-file YAML]
"""

from hexapod_description.launch_actions import (
    configured_node,
    operator_arguments,
    params_file_argument,
    state_publisher,
)
from launch import LaunchDescription

SIM = {
    'engine': "sim_node's physics engine (mujoco made the shipped repertoire)",
    'failed_legs': "legs (1-6) lifted in the simulator, e.g. '[1, 2]'",
}
NAVIGATE = {'record_dir': "one MCAP per goal ('' = no recording)"}


def generate_launch_description() -> LaunchDescription:
    return LaunchDescription(
        [
            params_file_argument('hexapod_navigation', 'navigate.yaml'),
            *operator_arguments(SIM | NAVIGATE),
            # one time base: every node but the clock source (sim_node) runs on sim time
            configured_node('hexapod_gait', 'gait_node', (), {'use_sim_time': True}),
            configured_node('hexapod_sim', 'sim_node', SIM),
            state_publisher(use_sim_time=True),
            configured_node(
                'hexapod_navigation',
                'navigate_node',
                NAVIGATE,
                {'mode': 'sim', 'use_sim_time': True},
            ),  # fmt: skip
        ]
    )
