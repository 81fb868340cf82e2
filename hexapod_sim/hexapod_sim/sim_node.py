# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``ros2 run hexapod_sim sim_node``: the simulated hexapod in the ROS graph (PyBullet or MuJoCo).

Plays the latest one-cycle ``gait/joint_trajectory`` (latched) cyclically from phase 0, with the
physics in its own thread (:mod:`hexapod_sim.physics.physics_loop`). Publishes ``/clock``; every
``publish_period_steps`` steps from the last reset ``odom`` (pose and twist, reliable) with
odom -> base_link on ``/tf``, ``joint_states``, ``imu/data`` and ``foot_contacts`` (sensor QoS);
latched ``sim/active_trajectory`` (the stamp being played), ``sim/last_reset``, ``sim/status``
and ``sim/damage``; ``sim/activations`` (the sim time each trajectory took effect, the last 64
kept). Services: ``~/set_leg_failure`` (hexapod_msgs/SetLegFailure), ``~/reset`` (std_srvs/
Trigger: back to the origin, damage kept, the gait from phase 0), ``~/get_damage``.

The state of "reset + N steps" is always published, so a trial reads it exactly; a reset also
publishes the pose at the origin stamped with the reset time (when a scheduled message has that
stamp too, the later one is the post-reset pose). docs/simulator.md has the details.
"""

from __future__ import annotations

import math
import sys

from diagnostic_msgs.msg import DiagnosticStatus
from hexapod_gait import preset
from hexapod_gait.trajectory import build_joint_table
from hexapod_msgs.msg import FootContacts, LegDamage, TrajectoryActivation
from hexapod_msgs.srv import GetLegDamage, SetLegFailure
from hexapod_sim import ros_conversions as conv
from hexapod_sim.damage import applied_message, Damage, damage_from_lists
from hexapod_sim.physics.engines import create_simulator
from hexapod_sim.physics.physics_loop import LoopHooks, PhysicsLoop, publish_period_steps
from hexapod_sim.sim_node_settings import PARAMETERS
from hexapod_sim.simulator import SimConfig
from hexapod_sim.trajectory_input import CycleTable, TrajectoryError
from hexapod_util.diagnostics import StatusHealth
from hexapod_util.guarded_logging import GuardedLogging
from hexapod_util.ros_glue import (
    declare,
    EVENTS,
    LATCHED,
    ODOM,
    odom_transform,
    publish_status,
    run_node,
    SENSOR,
    TF_QOS,
    watch_for_duplicates,
)
from nav_msgs.msg import Odometry
import numpy as np
from rcl_interfaces.msg import SetParametersResult
import rclpy
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from rclpy.node import Node
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu, JointState
from std_msgs.msg import Header
from std_srvs.srv import Trigger
from tf2_msgs.msg import TFMessage
from trajectory_msgs.msg import JointTrajectory


class SimNode(GuardedLogging, Node):
    """The simulated hexapod in the ROS graph (see the module docstring)."""

    def __init__(self, **kwargs) -> None:
        super().__init__('sim_node', **kwargs)
        values = declare(self, PARAMETERS)  # name -> value (None: unset)
        self.add_on_set_parameters_callback(self._on_set_parameters)

        rtf = float(values['real_time_factor'])
        if not (math.isfinite(rtf) and 0.0 <= rtf <= 100.0):
            raise ValueError(f'parameter real_time_factor must be in [0, 100], got {rtf}')
        engine, friction = str(values['engine']), values['friction']  # friction None: unset
        friction = None if friction is None else float(friction)
        config = SimConfig(engine, friction, gui=bool(values['gui']))
        substeps = int(values['substeps'])
        self.sim = create_simulator(config.with_substeps(substeps) if substeps else config)
        self.odom_frame = str(values['odom_frame'])
        self.base_frame = str(values['base_frame'])

        group = ReentrantCallbackGroup()
        self._make_publishers()
        # one at a time, in arrival order: in the reentrant group two trajectories close together
        # (a tipped trial's stand, then the next trial's gait) could switch in the wrong order,
        # leaving the older one playing (CI, 2026-11-28)
        self.create_subscription(
            JointTrajectory,
            'gait/joint_trajectory',
            self._on_trajectory,
            LATCHED,
            callback_group=MutuallyExclusiveCallbackGroup(),
        )
        self.create_service(
            SetLegFailure, '~/set_leg_failure', self._on_set_leg_failure, callback_group=group
        )
        self.create_service(Trigger, '~/reset', self._on_reset, callback_group=group)
        self.create_service(
            GetLegDamage, '~/get_damage', self._on_get_damage, callback_group=group
        )

        # Until a trajectory arrives the robot stands in the first pose of the control gait.
        stand = build_joint_table(preset('control'), rate=1.0 / self.sim.dt)
        cycle = CycleTable(stand.positions[:1], np.zeros_like(stand.positions[:1]), self.sim.dt)
        self._publish_errors: set[type] = set()
        hooks = LoopHooks(
            self._publish_state,
            lambda t: self.clock_pub.publish(Clock(clock=conv.stamp(t))),
            lambda t: self.reset_pub.publish(
                Header(stamp=conv.stamp(t), frame_id=self.odom_frame)
            ),
            self._on_unstable,
            self._on_publish_failed,
        )
        self.loop = PhysicsLoop(
            self.sim,
            cycle,
            hooks,
            rtf,
            publish_period_steps(int(values['publish_period_steps']), rtf),
            int(values['clock_period_steps']),
        )
        initial = values['failed_legs']
        try:
            self._apply_failure(Damage.lifted(list(initial or [])))
        except ValueError as exc:  # never start an intact robot when a damaged one was asked for
            raise ValueError(f'parameter failed_legs: {exc}') from None
        self.health = StatusHealth(  # its last status, also on /diagnostics
            self,
            'simulator',
            f'simulated robot, {engine} physics engine',
            self._values,
            'simulating',
        )
        watch_for_duplicates(self, lambda text: self._status(DiagnosticStatus.ERROR, text))
        self.get_logger().info(
            f'simulating with the {engine} engine at real_time_factor {rtf:g}, state every '
            f'{self.loop.period_steps} steps, {self.sim.settings.substeps} physics step(s) a step'
        )
        self.loop.start()

    def _make_publishers(self) -> None:
        self.clock_pub = self.create_publisher(Clock, '/clock', 10)
        self.joint_pub = self.create_publisher(JointState, 'joint_states', SENSOR)
        self.odom_pub = self.create_publisher(Odometry, 'odom', ODOM)
        self.tf_pub = self.create_publisher(TFMessage, '/tf', TF_QOS)
        self.imu_pub = self.create_publisher(Imu, 'imu/data', SENSOR)
        self.contacts_pub = self.create_publisher(FootContacts, 'foot_contacts', SENSOR)
        self.active_pub = self.create_publisher(Header, 'sim/active_trajectory', LATCHED)
        self.activation_pub = self.create_publisher(
            TrajectoryActivation, 'sim/activations', EVENTS
        )
        self.reset_pub = self.create_publisher(Header, 'sim/last_reset', LATCHED)
        self.status_pub = self.create_publisher(DiagnosticStatus, 'sim/status', LATCHED)
        self.damage_pub = self.create_publisher(LegDamage, 'sim/damage', LATCHED)

    # -- parameters / callbacks (executor threads) ---------------------------------------------
    def _on_set_parameters(self, params: list[Parameter]) -> SetParametersResult:
        for param in params:
            if param.name == 'real_time_factor':
                value = float(param.value)
                if not math.isfinite(value) or value < 0:
                    return SetParametersResult(
                        successful=False, reason='real_time_factor must be >= 0'
                    )
                self.loop.rtf = value
        return SetParametersResult(successful=True)

    def _on_trajectory(self, msg: JointTrajectory) -> None:
        try:
            cycle = conv.cycle_from_msg(msg, self.sim.model.joint_names, self.sim.dt)
        except TrajectoryError as exc:
            self._status(DiagnosticStatus.ERROR, f'trajectory rejected: {exc}; previous gait kept')
            return

        def switch() -> None:  # in the physics thread: no state is published half-way
            began = conv.stamp(self.loop.play(cycle))
            self.active_pub.publish(msg.header)
            self.activation_pub.publish(
                TrajectoryActivation(
                    header=Header(stamp=began, frame_id=self.odom_frame),
                    trajectory=msg.header.stamp,
                )
            )

        try:
            self.loop.call(switch)
        except TimeoutError as exc:
            self._status(DiagnosticStatus.ERROR, f'trajectory not applied: {exc}')
            return
        self._status(
            DiagnosticStatus.OK,
            f'playing a {len(cycle.positions)}-step cycle of {cycle.period:g} s',
        )

    def _on_set_leg_failure(
        self, request: SetLegFailure.Request, response: SetLegFailure.Response
    ):
        try:
            damage = damage_from_lists(
                list(request.failed_legs),
                list(request.kinds),
                list(request.strengths),
                list(request.joints),
            )
            applied = self.loop.call(lambda: self._apply_failure(damage))
        except ValueError as exc:
            response.success, response.message = False, f'refused: {exc}'
            response.failed_legs = list(self.sim.failed_legs)
            response.damage = self.sim.damage.label
            return response
        response.success = True
        response.failed_legs = list(applied.failed_legs)
        response.damage = applied.label
        response.message = applied_message(applied)
        self._status(DiagnosticStatus.OK, response.message)
        return response

    def _on_get_damage(self, request: GetLegDamage.Request, response: GetLegDamage.Response):
        response.damage = self.loop.call(
            lambda: conv.damage_msg(self.sim.damage, conv.stamp(self.loop.sim_time))
        )
        return response

    def _on_reset(self, request: Trigger.Request, response: Trigger.Response):
        t = self.loop.call(self.loop.reset)
        response.success = True
        response.message = f'reset at t={t:.9f} s; damage: {self.sim.damage.label}'
        return response

    def _status(self, level: bytes, message: str) -> None:
        publish_status(self, self.status_pub, level, message, 'hexapod_sim')
        self.health.update(level, message)

    def _values(self) -> dict[str, str]:
        return {'sim_time_s': f'{self.loop.sim_time:.2f}', 'damage': self.sim.damage.label}

    # -- physics thread ------------------------------------------------------------------------
    def _apply_failure(self, damage: Damage) -> Damage:
        applied = self.loop.set_damage(damage)
        self.damage_pub.publish(conv.damage_msg(applied, conv.stamp(self.loop.sim_time)))
        return applied

    def _on_unstable(self, t: float) -> None:
        self._status(
            DiagnosticStatus.ERROR,
            f'the {self.sim.engine} physics became unstable at sim time {t:.3f} s and was reset;'
            ' results since the last reset are not valid: call ~/reset',
        )

    def _on_publish_failed(self, exc: Exception) -> bool:
        """Report a failed publish once per kind; True when the node is shutting down."""
        if not rclpy.ok(context=self.context):
            return True  # shutting down: the context is gone
        if type(exc) not in self._publish_errors:
            self._publish_errors.add(type(exc))
            self.get_logger().error(f'publishing failed: {exc} (simulation continues)')
        return False

    def _publish_state(self, t: float) -> None:
        when, sim, base = conv.stamp(t), self.sim, self.base_frame
        odom = conv.odometry(sim, when, self.odom_frame, base)
        self.odom_pub.publish(odom)
        self.tf_pub.publish(TFMessage(transforms=[odom_transform(odom)]))
        self.joint_pub.publish(conv.joint_state(sim, when, base))
        self.imu_pub.publish(conv.imu(sim, when, base))
        self.contacts_pub.publish(conv.foot_contacts(sim, when, base))

    def shutdown(self) -> None:
        """Stop the physics thread and release the simulator (called by run_node)."""
        self.loop.stop()
        self.sim.close()


def main(args: list[str] | None = None) -> int:
    """Entry point of ``ros2 run hexapod_sim sim_node``."""
    return run_node(SimNode, args, num_threads=3, parameters=PARAMETERS)


if __name__ == '__main__':
    sys.exit(main())
