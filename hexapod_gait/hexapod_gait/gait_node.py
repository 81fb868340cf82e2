# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``ros2 run hexapod_gait gait_node``: gait parameters in, one joint-trajectory cycle out.

Subscribes  gait/parameters        hexapod_msgs/GaitParameters   (latched, depth 1)
Publishes   gait/joint_trajectory  trajectory_msgs/JointTrajectory (latched): one full cycle
            gait/status            diagnostic_msgs/DiagnosticStatus (latched): accepted/rejected
An invalid or unreachable gait is rejected with its reason; the previous trajectory stays.
The trajectory's header stamp echoes the stamp of the GaitParameters it was built from (or
the current time if that was zero), so a consumer can tell which request it answers.
"""

from __future__ import annotations

import sys

from diagnostic_msgs.msg import DiagnosticStatus
from hexapod_description import load_model
from hexapod_gait.parameters import GaitParameterError, GaitParameters
from hexapod_gait.presets import preset, PRESETS
from hexapod_gait.ros_conversions import gait_from_msg, table_to_trajectory
from hexapod_gait.trajectory import build_joint_table, ReachabilityError, samples_per_cycle
from hexapod_msgs.msg import GaitParameters as GaitParametersMsg
from hexapod_util.diagnostics import StatusHealth
from hexapod_util.guarded_logging import GuardedLogging
from hexapod_util.ros_glue import declare, LATCHED, ParamSpec, publish_status, run_node
from rclpy.node import Node
from trajectory_msgs.msg import JointTrajectory

PARAMETERS = (
    ParamSpec(
        'control_rate',
        240.0,
        'Trajectory sample rate [Hz]: 240 for the simulator, 120 for the robot. '
        'period x rate must be a whole number.',
        read_only=True,
        range=(10.0, 2000.0),
    ),
    ParamSpec(
        'initial_preset',
        'tripod',
        f"Gait published at start-up: one of {', '.join(PRESETS)}, or '' for none",
        read_only=True,
    ),
    ParamSpec(
        'frame_id', 'base_link', 'frame_id of the published trajectory header', read_only=True
    ),
)


class GaitNode(GuardedLogging, Node):
    """Gait parameters in, one joint-trajectory cycle out (see the module docstring)."""

    def __init__(self, **kwargs) -> None:
        super().__init__('gait_node', **kwargs)
        declare(self, PARAMETERS)
        self.rate = float(self.get_parameter('control_rate').value)
        self.frame_id = str(self.get_parameter('frame_id').value)
        self.joint_names = load_model().joint_names
        self.active: GaitParameters | None = None

        self.trajectory_pub = self.create_publisher(
            JointTrajectory, 'gait/joint_trajectory', LATCHED
        )
        self.status_pub = self.create_publisher(DiagnosticStatus, 'gait/status', LATCHED)
        self.health = StatusHealth(self, 'gait', 'gait controller', message='no gait yet')
        self.create_subscription(GaitParametersMsg, 'gait/parameters', self.on_parameters, LATCHED)

        name = str(self.get_parameter('initial_preset').value)
        if name:
            try:
                self.apply(preset(name), source=f"preset '{name}'")
            except ValueError as exc:
                self.get_logger().error(f'initial_preset: {exc}; starting without a gait')

    def on_parameters(self, msg: GaitParametersMsg) -> None:
        """Handle a GaitParameters message: build and publish its trajectory, or refuse it."""
        try:
            gait = gait_from_msg(msg)
        except GaitParameterError as exc:
            self.reject(f'invalid gait parameters: {exc}', msg.archive_index)
            return
        self.apply(
            gait,
            source=f'gait/parameters (archive index {msg.archive_index})',
            stamp=msg.header.stamp,
        )

    def apply(self, gait: GaitParameters, source: str, stamp=None) -> bool:
        """Build the joint table of ``gait`` and publish it; False if it cannot be followed."""
        try:
            samples_per_cycle(gait.period, self.rate)
            table = build_joint_table(gait, rate=self.rate)
        except (ReachabilityError, ValueError) as exc:
            self.reject(f'gait from {source} rejected: {exc}', gait.archive_index)
            return False
        traj = table_to_trajectory(table, self.joint_names)
        traj.header.frame_id = self.frame_id
        has_stamp = stamp is not None and (stamp.sec != 0 or stamp.nanosec != 0)
        traj.header.stamp = stamp if has_stamp else self.get_clock().now().to_msg()
        self.trajectory_pub.publish(traj)
        self.active = gait
        self.publish_status(
            DiagnosticStatus.OK,
            f'active gait from {source}: {len(table)} points at {self.rate:g} Hz',
            gait.archive_index,
        )
        return True

    def reject(self, reason: str, archive_index: int) -> None:
        """Report a refused gait; the previous trajectory stays active."""
        kept = 'previous trajectory kept' if self.active is not None else 'no trajectory active'
        self.publish_status(DiagnosticStatus.ERROR, f'{reason} ({kept})', archive_index)

    def publish_status(self, level: bytes, message: str, archive_index: int) -> None:
        """Log and publish gait/status with the gait's archive index (and the active one's)."""
        values = {'archive_index': archive_index}
        if self.active is not None:
            values['active_archive_index'] = self.active.archive_index
        publish_status(self, self.status_pub, level, message, 'hexapod', **values)
        self.health.update(level, message)


def main(args: list[str] | None = None) -> int:
    """Entry point of ``ros2 run hexapod_gait gait_node``."""
    return run_node(GaitNode, args, num_threads=1, parameters=PARAMETERS)


if __name__ == '__main__':
    sys.exit(main())
