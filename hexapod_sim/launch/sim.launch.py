"""Simulated robot: gait_node + sim_node (full ROS 2 Jazzy install).

    ros2 launch hexapod_sim sim.launch.py real_time_factor:=0.0 failed_legs:='[1]'
In this workspace without `launch`: python scripts/launch.py sim
"""
from pathlib import Path

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


URDF = Path(get_package_share_directory("hexapod_description")) / "urdf" / "hexapod.urdf"


def generate_launch_description() -> LaunchDescription:
    rtf = LaunchConfiguration("real_time_factor")
    return LaunchDescription([
        DeclareLaunchArgument("real_time_factor", default_value="1.0",
                              description="simulated seconds per wall second; 0 = as fast as possible"),
        DeclareLaunchArgument("initial_preset", default_value="tripod"),
        DeclareLaunchArgument("gui", default_value="false"),
        DeclareLaunchArgument("publish_period_steps", default_value="4",
                              description="state topics every N 1/240 s steps; 24 suits real_time_factor 0"),
        Node(package="hexapod_gait", executable="gait_node", output="screen",
             parameters=[{"initial_preset": LaunchConfiguration("initial_preset"), "control_rate": 240.0,
                          "use_sim_time": True}]),     # sim_node's /clock: one time base
        Node(package="hexapod_sim", executable="sim_node", output="screen",
             parameters=[{"real_time_factor": rtf, "gui": LaunchConfiguration("gui"),
                          "publish_period_steps": LaunchConfiguration("publish_period_steps")}]),
        # the leg links on /tf and the latched robot_description (odom -> base_link: sim_node)
        Node(package="robot_state_publisher", executable="robot_state_publisher", output="screen",
             parameters=[{"robot_description": URDF.read_text(), "use_sim_time": True}]),
    ])
