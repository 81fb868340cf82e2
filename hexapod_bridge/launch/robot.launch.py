# Copyright 2026 Hexapod adaptation team
# All rights reserved.
#
# Permission is hereby granted, free of charge, to any person obtaining a copy
# of this software and associated documentation files (the "Software"), to deal
# in the Software without restriction, including without limitation the rights
# to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
# copies of the Software, and to permit persons to whom the Software is
# furnished to do so, subject to the following conditions:
#
# The above copyright notice and this permission notice shall be included in all
# copies or substantial portions of the Software.
#
# THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
# IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
# FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
# AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
# LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
# OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
# SOFTWARE.
"""
Real robot: bridge_node on the radio (and optionally an Xsens) port (full ROS 2 Jazzy install).

    ros2 launch hexapod_bridge robot.launch.py port:=/dev/ttyUSB0 imu_port:=/dev/ttyUSB1
In this workspace without `launch`: python scripts/launch.py robot --port /dev/ttyUSB0
"""

from hexapod_description.launch_actions import state_publisher
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description() -> LaunchDescription:
    return LaunchDescription(
        [
            DeclareLaunchArgument('port', default_value='/dev/ttyUSB0'),
            DeclareLaunchArgument('imu_port', default_value=''),
            DeclareLaunchArgument('firmware', default_value='v2'),
            Node(
                package='hexapod_bridge',
                executable='bridge_node',
                output='screen',
                parameters=[
                    {
                        'port': LaunchConfiguration('port'),
                        'imu_port': LaunchConfiguration('imu_port'),
                        'firmware': LaunchConfiguration('firmware'),
                    }
                ],
            ),
            # the latched robot_description and /tf_static, so recordings replay in 3D; the
            # odom -> base_link transform comes from bridge_node's IMU odometry
            state_publisher(),
        ]
    )
