# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``ros2 run hexapod_gait state_publisher``.

The robot model for RViz and Foxglove where ``robot_state_publisher`` is not installed (on a full
ROS 2 install the launch files start that).

Publishes   robot_description  std_msgs/String (latched): the URDF
            /tf_static         tf2_msgs/TFMessage (latched): the fixed joints (foot frames)
            /tf                tf2_msgs/TFMessage: every leg link in its parent's frame, at the
                               stamp of each joint_states message
Subscribes  joint_states       sensor_msgs/JointState
The odom -> base_link transform comes from sim_node (or bridge_node).
"""

from __future__ import annotations

from pathlib import Path
import sys

from geometry_msgs.msg import TransformStamped
from hexapod_description import robot_description_path
from hexapod_description.tf_tree import joint_frames, moving_transforms, static_transforms
from hexapod_util.diagnostics import StatusHealth
from hexapod_util.guarded_logging import GuardedLogging
from hexapod_util.ros_glue import declare, LATCHED, ParamSpec, run_node, SENSOR, TF_QOS
from rclpy.node import Node
from sensor_msgs.msg import JointState
from std_msgs.msg import String
from tf2_msgs.msg import TFMessage

PARAMETERS = (
    ParamSpec('urdf', '', "URDF file to publish ('' = hexapod_description's)", read_only=True),
)


def transform_msg(parent: str, child: str, xyz, quat, stamp) -> TransformStamped:
    """Return a TransformStamped of ``child`` in ``parent``."""
    t = TransformStamped()
    t.header.stamp, t.header.frame_id, t.child_frame_id = stamp, parent, child
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = (
        float(v) for v in xyz
    )
    r = t.transform.rotation
    r.x, r.y, r.z, r.w = (float(v) for v in quat)
    return t


class StatePublisher(GuardedLogging, Node):
    """robot_description, /tf_static and the leg links' /tf from joint_states."""

    def __init__(self) -> None:
        super().__init__('state_publisher')
        path = Path(declare(self, PARAMETERS)['urdf'] or robot_description_path())
        if not path.is_file():
            raise ValueError(f'parameter urdf: no such file {path}')
        self.frames = joint_frames(path)
        self.create_publisher(String, 'robot_description', LATCHED).publish(
            String(data=path.read_text())
        )
        stamp = self.get_clock().now().to_msg()
        statics = [
            transform_msg(f.parent, f.child, xyz, q, stamp)
            for f, xyz, q in static_transforms(self.frames)
        ]
        self.create_publisher(TFMessage, '/tf_static', LATCHED).publish(
            TFMessage(transforms=statics)
        )
        self.tf_pub = self.create_publisher(TFMessage, '/tf', TF_QOS)
        self.create_subscription(JointState, 'joint_states', self._on_joint_states, SENSOR)
        said = f'publishing {path.name}: {len(self.frames)} joints, {len(statics)} static'
        self.get_logger().info(said)
        self.health = StatusHealth(self, 'robot model', f'URDF {path}', message=said)

    def _on_joint_states(self, msg: JointState) -> None:
        if len(msg.name) != len(msg.position):
            self.get_logger().warning(
                'joint_states with names and positions of different lengths ignored'
            )
            return
        positions = dict(zip(msg.name, msg.position))
        self.tf_pub.publish(
            TFMessage(
                transforms=[
                    transform_msg(f.parent, f.child, xyz, q, msg.header.stamp)
                    for f, xyz, q in moving_transforms(self.frames, positions)
                ]
            )
        )


def main(args: list[str] | None = None) -> int:
    """Entry point of ``ros2 run hexapod_gait state_publisher``."""
    return run_node(StatePublisher, args, parameters=PARAMETERS)


if __name__ == '__main__':
    sys.exit(main())
