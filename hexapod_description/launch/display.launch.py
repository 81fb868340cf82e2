"""Publish the hexapod's TF tree from its URDF (full ROS 2 Jazzy install only).

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
