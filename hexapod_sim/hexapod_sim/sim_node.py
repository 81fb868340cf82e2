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
``ros2 run hexapod_sim sim_node``.

The simulated hexapod in the ROS graph (PyBullet by default, or MuJoCo with ``engine:=mujoco``).

Subscribes  gait/joint_trajectory  trajectory_msgs/JointTrajectory (latched): one gait cycle,
                                   played cyclically from phase 0 as soon as it arrives
Publishes   /clock                 rosgraph_msgs/Clock, every clock_period_steps steps
            joint_states           sensor_msgs/JointState        (sensor-data QoS)
            odom                   nav_msgs/Odometry, odom -> base_link, pose and twist (reliable)
            /tf                    tf2_msgs/TFMessage: odom -> base_link with each odometry
            imu/data               sensor_msgs/Imu               (sensor-data QoS)
            foot_contacts          hexapod_msgs/FootContacts     (sensor-data QoS)
            sim/active_trajectory  std_msgs/Header (latched): stamp of the trajectory being played
            sim/activations        hexapod_msgs/TrajectoryActivation (the last 64 kept): the
                                   simulation time each trajectory took effect, for timing a
                                   walk by the simulation's clock however late its reader is
            sim/last_reset         std_msgs/Header (latched): sim time of the last reset
            sim/status             diagnostic_msgs/DiagnosticStatus (latched): last error/event
            sim/damage             hexapod_msgs/LegDamage (latched): the robot's damage, at
                                   start-up and after each change (for adapt_node's prior)
Services    ~/set_leg_failure      hexapod_msgs/SetLegFailure
            ~/reset                std_srvs/Trigger: robot back to the origin, damage kept,
                                   gait restarted at phase 0
            ~/get_damage           hexapod_msgs/GetLegDamage: the damage now (sim/damage's)
State topics are published every ``publish_period_steps`` steps counted from the last reset,
so the odometry of "reset + N steps" is always published: a trial reads it exactly. A reset also
publishes the pose at the origin stamped with the reset time; when a scheduled message was just
published with that same stamp, the later one (messages arrive in order) is the post-reset pose.
The physics runs in its own thread; callbacks hand work to it and wait until it is applied.
"""

from __future__ import annotations

import math
import queue
import sys
import threading
import time
from typing import Callable

from builtin_interfaces.msg import Time
from diagnostic_msgs.msg import DiagnosticStatus
from hexapod_gait import preset
from hexapod_gait.ros_glue import (
    declare,
    EVENTS,
    LATCHED,
    ODOM,
    odom_transform,
    ParamSpec,
    publish_status,
    run_node,
    SENSOR,
    TF_QOS,
    watch_for_duplicates,
)
from hexapod_gait.trajectory import build_joint_table
from hexapod_msgs.msg import FootContacts, LegDamage, TrajectoryActivation
from hexapod_msgs.srv import GetLegDamage, SetLegFailure
from hexapod_sim.damage import Damage, damage_from_lists
from hexapod_sim.engines import create_simulator
from hexapod_sim.simulator import DEFAULT_FRICTION, SimConfig
from hexapod_sim.trajectory_input import cycle_from_points, CycleTable, MAX_POINTS, TrajectoryError
from nav_msgs.msg import Odometry
import numpy as np
from rcl_interfaces.msg import SetParametersResult
import rclpy
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.node import Node
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu, JointState
from std_msgs.msg import Header
from std_srvs.srv import Trigger
from tf2_msgs.msg import TFMessage
from trajectory_msgs.msg import JointTrajectory


def _stamp(seconds: float) -> Time:
    ns = int(round(seconds * 1e9))
    return Time(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)


PARAMETERS = (
    ParamSpec(
        'real_time_factor',
        1.0,
        'Simulated seconds per wall-clock second; 0 = as fast as possible',
        range=(0.0, 100.0),
    ),
    ParamSpec(
        'engine',
        'pybullet',
        "Physics engine: 'pybullet' (the thesis's, the reference) or 'mujoco' (fast)",
        read_only=True,
    ),
    ParamSpec('gui', False, 'Open the PyBullet GUI window (engine pybullet only)', read_only=True),
    ParamSpec(
        'friction',
        Parameter.Type.DOUBLE,
        "Lateral friction coefficient of the ground and the feet (unset = the engine's default: "
        + ', '.join(f'{engine} {value:g}' for engine, value in DEFAULT_FRICTION.items())
        + ')',
        read_only=True,
        range=(0.0, 10.0),
    ),
    ParamSpec(
        'failed_legs',
        Parameter.Type.INTEGER_ARRAY,
        'Legs (1..6, at most two) failed at start-up',
        read_only=True,
    ),
    ParamSpec(
        'publish_period_steps',
        4,
        'Publish joint_states/odom/imu/foot_contacts every N physics steps (1/240 s each). With'
        ' real_time_factor 0 the node runs ~18x real time; use 24 (10 Hz of sim time) so Python'
        ' consumers keep up. Trials read odometry at reset + N steps exactly.',
        read_only=True,
        range=(1, 240),
    ),
    ParamSpec(
        'clock_period_steps',
        6,
        'Publish /clock every N physics steps (6: 40 Hz of sim time) and with every state'
        ' message. Each /clock message wakes every node on use_sim_time: at every step (240 Hz)'
        " a Python node's multi-threaded executor took a whole core (docs/simulator.md).",
        read_only=True,
        range=(1, 240),
    ),
    ParamSpec('odom_frame', 'odom', 'REP 105 odometry frame', read_only=True),
    ParamSpec('base_frame', 'base_link', 'Robot base frame', read_only=True),
)


class SimNode(Node):
    """The simulated hexapod in the ROS graph (see the module docstring)."""

    def __init__(self, **kwargs) -> None:
        super().__init__('sim_node', **kwargs)
        declare(self, PARAMETERS)
        self.add_on_set_parameters_callback(self._on_set_parameters)

        self.rtf = float(self.get_parameter('real_time_factor').value)
        if not (math.isfinite(self.rtf) and 0.0 <= self.rtf <= 100.0):
            raise ValueError(f'parameter real_time_factor must be in [0, 100], got {self.rtf}')
        engine = str(self.get_parameter('engine').value)
        friction = self.get_parameter_or('friction', Parameter('friction', value=None)).value
        self.sim = create_simulator(
            SimConfig(
                engine=engine,
                friction=None if friction is None else float(friction),
                gui=bool(self.get_parameter('gui').value),
            )
        )
        self.period_steps = int(self.get_parameter('publish_period_steps').value)
        self.clock_steps = int(self.get_parameter('clock_period_steps').value)
        self.odom_frame = str(self.get_parameter('odom_frame').value)
        self.base_frame = str(self.get_parameter('base_frame').value)

        group = ReentrantCallbackGroup()
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
        self.create_subscription(
            JointTrajectory,
            'gait/joint_trajectory',
            self._on_trajectory,
            LATCHED,
            callback_group=group,
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
        self.cycle = CycleTable(
            stand.positions[:1], np.zeros_like(stand.positions[:1]), self.sim.dt
        )
        self.cycle_stamp = Header()
        self._prepare_cycle()
        initial = (
            self.get_parameter_or('failed_legs', Parameter('failed_legs', value=[])).value or []
        )
        try:
            self._apply_failure(Damage.lifted(list(initial)))
        except ValueError as exc:  # never start an intact robot when a damaged one was asked for
            raise ValueError(f'parameter failed_legs: {exc}') from None
        self._work: queue.Queue[Callable[[], None]] = queue.Queue()
        self._reset_now()
        self._running = True
        self._publish_errors: set[type] = set()
        self._thread = threading.Thread(target=self._run, name='physics', daemon=True)
        self._thread.start()
        watch_for_duplicates(self, lambda text: self._status(DiagnosticStatus.ERROR, text))
        self.get_logger().info(
            f'simulating with the {engine} engine at real_time_factor {self.rtf:g}'
        )

    # -- parameters / callbacks (executor threads) ---------------------------------------------
    def _on_set_parameters(self, params: list[Parameter]) -> SetParametersResult:
        for param in params:
            if param.name == 'real_time_factor':
                value = float(param.value)
                if not math.isfinite(value) or value < 0:
                    return SetParametersResult(
                        successful=False, reason='real_time_factor must be >= 0'
                    )
                self.rtf = value
        return SetParametersResult(successful=True)

    def _in_physics_thread(self, work: Callable[[], object], timeout: float = 10.0) -> object:
        """Run work between two physics steps; return its result (or raise its exception)."""
        done = threading.Event()
        box: dict[str, object] = {}

        def wrapped() -> None:
            try:
                box['result'] = work()
            except Exception as exc:  # handed back to the caller
                box['error'] = exc
            finally:
                done.set()

        self._work.put(wrapped)
        if not done.wait(timeout):
            raise TimeoutError('the physics thread did not respond')
        if 'error' in box:
            raise box['error']  # type: ignore[misc]
        return box.get('result')

    def _on_trajectory(self, msg: JointTrajectory) -> None:
        if len(msg.points) > MAX_POINTS:  # refuse before copying anything out of the message
            self._status(
                DiagnosticStatus.ERROR,
                f'trajectory rejected: a gait cycle may have at most {MAX_POINTS} '
                f'points, got {len(msg.points)}; previous gait kept',
            )
            return
        try:
            cycle = cycle_from_points(
                msg.joint_names,
                [pt.time_from_start.sec + pt.time_from_start.nanosec * 1e-9 for pt in msg.points],
                [list(pt.positions) for pt in msg.points],
                [list(pt.velocities) for pt in msg.points],
                self.sim.model.joint_names,
                self.sim.dt,
            )
        except TrajectoryError as exc:
            self._status(DiagnosticStatus.ERROR, f'trajectory rejected: {exc}; previous gait kept')
            return

        def switch() -> None:
            self.cycle, self.cycle_stamp = cycle, msg.header
            self._prepare_cycle()
            self.active_pub.publish(msg.header)
            self.activation_pub.publish(
                TrajectoryActivation(
                    header=Header(stamp=_stamp(self._sim_time), frame_id=self.odom_frame),
                    trajectory=msg.header.stamp,
                )
            )

        try:
            self._in_physics_thread(switch)
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
                list(request.failed_legs), list(request.kinds), list(request.strengths)
            )
            applied = self._in_physics_thread(lambda: self._apply_failure(damage))
        except ValueError as exc:
            response.success, response.message = False, f'refused: {exc}'
            response.failed_legs = list(self.sim.failed_legs)
            response.damage = self.sim.damage.label
            return response
        response.success = True
        response.failed_legs = list(applied.failed_legs)
        response.damage = applied.label
        response.message = (
            f'failed legs: {list(applied.failed_legs) or "none"}'
            if applied.thesis
            else f'damage: {applied.label}'
        )
        self._status(DiagnosticStatus.OK, response.message)
        return response

    def _on_get_damage(self, request: GetLegDamage.Request, response: GetLegDamage.Response):
        response.damage = self._in_physics_thread(lambda: self._damage_msg(self.sim.damage))
        return response

    def _on_reset(self, request: Trigger.Request, response: Trigger.Response):
        t = self._in_physics_thread(self._reset_now)
        response.success, response.message = (
            True,
            f'reset at t={t:.9f} s; damage: {self.sim.damage.label}',
        )
        return response

    def _status(self, level: bytes, message: str) -> None:
        publish_status(self, self.status_pub, level, message, 'hexapod_sim')

    # -- physics thread ------------------------------------------------------------------------
    def _apply_failure(self, damage: Damage) -> Damage:
        applied = self.sim.set_damage(damage)
        self.damage_pub.publish(self._damage_msg(applied))
        self._prepare_cycle()
        return applied

    def _damage_msg(self, damage: Damage) -> LegDamage:
        """Return ``damage`` as sim/damage says it, stamped with the simulation time."""
        return LegDamage(
            header=Header(stamp=_stamp(getattr(self, '_sim_time', 0.0))),
            failed_legs=list(damage.failed_legs),
            kinds=[d.kind for d in damage.legs],
            strengths=[float(d.strength) for d in damage.legs],
            label=damage.label,
        )

    def _prepare_cycle(self) -> None:
        self._rows = self.sim.prepare_rows(self.cycle.positions, self.cycle.velocities)
        self._n_rows = len(self.cycle.positions)
        self._row = 0

    def _reset_now(self) -> float:
        q0 = self.cycle.positions[0]
        self.sim.reset(q0)
        if not hasattr(self, '_sim_time'):
            self._sim_time = 0.0
        self._steps_since_reset = 0
        self._unstable_reported = False
        self._row = 0
        self._reset_stamp = self._sim_time
        self.reset_pub.publish(Header(stamp=_stamp(self._sim_time), frame_id=self.odom_frame))
        self._publish_state()
        return self._sim_time

    def _run(self) -> None:
        wall_start, sim_start = time.monotonic(), self._sim_time
        rtf_seen = self.rtf
        while self._running:
            while True:
                try:
                    self._work.get_nowait()()
                except queue.Empty:
                    break
            sim = self.sim
            sim.apply_row(self._rows, self._row)
            if sim.step().unstable and not self._unstable_reported:
                self._unstable_reported = (
                    True  # once per reset: a bad setting repeats it every step
                )
                self._status(
                    DiagnosticStatus.ERROR,
                    f'the {sim.engine} physics became unstable at sim time '
                    f'{self._sim_time:.3f} s and was reset; results since the last '
                    'reset are not valid: call ~/reset',
                )
            sim.update_imu()
            self._row = (self._row + 1) % self._n_rows
            self._steps_since_reset += 1
            self._sim_time = self._reset_stamp + self._steps_since_reset * sim.dt
            try:
                state = self._steps_since_reset % self.period_steps == 0
                if state or self._steps_since_reset % self.clock_steps == 0:
                    self.clock_pub.publish(Clock(clock=_stamp(self._sim_time)))
                if state:
                    self._publish_state()
            except Exception as exc:
                if not self._running or not rclpy.ok(context=self.context):
                    return  # shutting down: the context is gone
                # a failed publish must not stop the physics: report once per kind, go on
                if type(exc) not in self._publish_errors:
                    self._publish_errors.add(type(exc))
                    self.get_logger().error(f'publishing failed: {exc} (simulation continues)')
            if self.rtf != rtf_seen:
                wall_start, sim_start, rtf_seen = time.monotonic(), self._sim_time, self.rtf
            if self.rtf > 0:
                ahead = (self._sim_time - sim_start) / self.rtf - (time.monotonic() - wall_start)
                if ahead > 0:
                    time.sleep(ahead)

    def _publish_state(self) -> None:
        stamp = _stamp(self._sim_time)
        sim = self.sim
        pos, quat = sim.base_pose()
        lin_b, ang_b = sim.base_twist_body()
        odom = Odometry()
        odom.header.stamp, odom.header.frame_id, odom.child_frame_id = (
            stamp,
            self.odom_frame,
            self.base_frame,
        )
        o = odom.pose.pose
        o.position.x, o.position.y, o.position.z = (float(v) for v in pos)
        o.orientation.x, o.orientation.y, o.orientation.z, o.orientation.w = (
            float(v) for v in quat
        )
        t = odom.twist.twist  # REP: twist is expressed in the child frame
        t.linear.x, t.linear.y, t.linear.z = (float(v) for v in lin_b)
        t.angular.x, t.angular.y, t.angular.z = (float(v) for v in ang_b)
        self.odom_pub.publish(odom)
        self.tf_pub.publish(TFMessage(transforms=[odom_transform(odom)]))

        q, qd, effort = sim.joint_states()
        self.joint_pub.publish(
            JointState(
                header=Header(stamp=stamp, frame_id=self.base_frame),
                name=list(sim.model.joint_names),
                position=q.tolist(),
                velocity=qd.tolist(),
                effort=effort.tolist(),
            )
        )
        iq, iw, ia = sim.imu()
        imu = Imu(header=Header(stamp=stamp, frame_id=self.base_frame))
        imu.orientation.x, imu.orientation.y, imu.orientation.z, imu.orientation.w = (
            float(v) for v in iq
        )
        imu.angular_velocity.x, imu.angular_velocity.y, imu.angular_velocity.z = (
            float(v) for v in iw
        )
        imu.linear_acceleration.x, imu.linear_acceleration.y, imu.linear_acceleration.z = (
            float(v) for v in ia
        )
        self.imu_pub.publish(imu)
        self.contacts_pub.publish(
            FootContacts(
                header=Header(stamp=stamp, frame_id=self.base_frame),
                in_contact=[bool(c) for c in sim.report.contacts],
            )
        )

    def shutdown(self) -> None:
        """Stop the physics thread and release the simulator (called by run_node)."""
        self._running = False
        if self._thread.is_alive():
            self._thread.join(timeout=5.0)
        self.sim.close()


def main(args: list[str] | None = None) -> int:
    """Entry point of ``ros2 run hexapod_sim sim_node``."""
    return run_node(SimNode, args, num_threads=3, parameters=PARAMETERS)


if __name__ == '__main__':
    sys.exit(main())
