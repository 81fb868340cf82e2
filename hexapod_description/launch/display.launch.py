"""Publish the hexapod's TF tree and robot_description from its URDF (full ROS 2 Jazzy install;
joint angles come from joint_states: sim_node or bridge_node). Without robot_state_publisher,
``ros2 run hexapod_gait state_publisher`` does the same.

    ros2 launch hexapod_description display.launch.py
"""
from pathlib import Path

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description() -> LaunchDescription:
    urdf = Path(get_package_share_directory("hexapod_description")) / "urdf" / "hexapod.urdf"
    return LaunchDescription([
        Node(package="robot_state_publisher", executable="robot_state_publisher",
             parameters=[{"robot_description": urdf.read_text()}]),
    ])
