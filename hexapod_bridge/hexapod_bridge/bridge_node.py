# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``ros2 run hexapod_bridge bridge_node``: the base station's link to the real hexapod.

Uploads each ``gait/parameters`` to the robot and walks its trials; publishes ``imu/data``,
``trial_result`` (one per trial: walked and measured whole or not, why, the IMU estimate),
``trial_odom`` (valid trials), ``odom`` with odom -> base_link on ``/tf``, the commanded
``joint_states``, ``~/link_status``, ``bridge/status``, ``servo_failures`` and ``/diagnostics``.
A lifecycle node (configure opens the ports, activate arms). Services: ``~/arm``,
``~/upload_gait``, ``~/start_trial``, ``~/stop_trial``, ``~/emergency_stop``, ``~/motor_power``,
``~/check_servos``, ``~/get_servo_failures``. docs/bridge.md says what each does.
"""

from __future__ import annotations

from dataclasses import asdict
import sys
import threading
import time

from diagnostic_msgs.msg import DiagnosticStatus
from hexapod_bridge import ros_conversions as conv
from hexapod_bridge.bridge_settings import JOINT_STATES_HZ, LEVELS, PARAMETERS, SERVO_CHECK_TRIES
from hexapod_bridge.commanded import CommandedJoints
from hexapod_bridge.gait_uploads import GaitUploads
from hexapod_bridge.health import imu_health, link_health, servo_health
from hexapod_bridge.lifecycle import ACTIVE, BridgeLifecycle, INACTIVE
from hexapod_bridge.odometry import ChainedPose
from hexapod_bridge.reports import Report, servo_report, trial_report
from hexapod_bridge.station import ServoCheck, TrialResult
from hexapod_description.model import load_model
from hexapod_msgs.msg import GaitParameters as GaitParametersMsg
from hexapod_msgs.msg import LinkStatus, RobotTrial, ServoFailure
from hexapod_msgs.srv import GetServoFailures, UploadGait
from hexapod_util.diagnostics import DiagnosticsPublisher
from hexapod_util.guarded_logging import GuardedLogging
from hexapod_util.health import Health
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
    TRIALS,
    unless_closing,
)
from nav_msgs.msg import Odometry
import rclpy
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.lifecycle import LifecycleNode
from sensor_msgs.msg import Imu, JointState
from std_srvs.srv import SetBool, Trigger
from tf2_msgs.msg import TFMessage


class BridgeNode(BridgeLifecycle, GaitUploads, GuardedLogging, LifecycleNode):
    """The base station's link to the robot's radio and IMU (see the module docstring)."""

    def __init__(self, **kwargs) -> None:
        super().__init__('bridge_node', **kwargs)
        self.values = v = declare(self, PARAMETERS)
        self.diagnostics = None
        self.link_problem = 'not configured'  # why there is no link ('' once configured)
        self.pending_gait = None  # the last gait/parameters, uploaded once configured
        self.frames = {k: str(v[f'{k}_frame']) for k in ('odom', 'base', 'imu')}
        self.dead: dict[int, float] = {}  # servo -> when reported dead (monotonic s)
        self.failures: dict[int, ServoFailure] = {}  # servo -> its report (~/get_servo_failures)
        self.imu_last: float | None = None  # when the last IMU message came (monotonic s)
        self._checking = threading.Lock()  # held while a start-up servo check runs
        imu = f'Xsens MTi on {v["imu_port"]}' if v['imu_port'] else "robot's attitude telemetry"
        group = ReentrantCallbackGroup()
        self.imu_pub = self.create_publisher(Imu, 'imu/data', SENSOR)
        self.pose = ChainedPose()  # odom -> base_link: the trials so far, chained
        self.odom_pub = self.create_publisher(Odometry, 'odom', ODOM)
        self.trial_odom_pub = self.create_publisher(Odometry, 'trial_odom', ODOM)
        self.trial_result_pub = self.create_publisher(RobotTrial, 'trial_result', TRIALS)
        self.tf_pub = self.create_publisher(TFMessage, '/tf', TF_QOS)
        self.link_pub = self.create_publisher(LinkStatus, '~/link_status', 10)
        self.status_pub = self.create_publisher(DiagnosticStatus, 'bridge/status', LATCHED)
        # every servo-failure report; kept for late joiners (an adapt node started afterwards)
        self.servo_pub = self.create_publisher(ServoFailure, 'servo_failures', EVENTS)
        self.unknown_servo_reports = 0
        self.create_subscription(
            GaitParametersMsg, 'gait/parameters', self._on_gait, LATCHED, callback_group=group
        )
        for srv, name, callback in (
            (SetBool, '~/arm', self._on_arm),
            (Trigger, '~/start_trial', self._on_start),
            (UploadGait, '~/upload_gait', self._on_upload_gait),
            (SetBool, '~/motor_power', self._on_motor_power),
            (Trigger, '~/stop_trial', self._on_stop),
            (Trigger, '~/emergency_stop', self._on_estop),
            (Trigger, '~/check_servos', self._on_check_servos),
            (GetServoFailures, '~/get_servo_failures', self._on_get_servo_failures),
        ):
            self.create_service(srv, name, callback, callback_group=group)
        self.create_timer(1.0 / float(v['status_rate']), self._tick, callback_group=group)
        # the robot in 3D: odom -> base_link and the commanded angles (none measured on the radio)
        self.commanded, self.joint_names = CommandedJoints(), load_model().joint_names
        self.joints_pub = self.create_publisher(JointState, 'joint_states', SENSOR)
        self.create_timer(1.0 / JOINT_STATES_HZ, self._publish_state, callback_group=group)
        self.diagnostics = DiagnosticsPublisher(self, lambda: self._health(imu))
        self.start_lifecycle()

    def _health(self, imu: str) -> list[Health]:
        now, v = time.monotonic(), self.values
        snapshot = self.station.snapshot(now) if self.station is not None else None
        return servo_health(self.dead, v['leg_map'], now) + [
            link_health(snapshot, str(v['port']), f'{self.state_label()}: {self.link_problem}'),
            imu_health(self.imu_last, now, imu),
        ]

    def unconfigured(self, response):
        """Fill a Trigger / SetBool response that refuses: the node has no ports open."""
        response.success = False
        response.message = f'bridge_node is {self.state_label()}: configure it first'
        return response

    def _status(self, level: bytes, message: str, **values) -> None:
        publish_status(self, self.status_pub, level, message, 'hexapod', **values)

    def _alive(self) -> bool:
        return rclpy.ok(context=self.context)

    # -- trials and power ------------------------------------------------------------------
    def _on_arm(self, request: SetBool.Request, response: SetBool.Response):
        """Activate (arm) or deactivate (stop the robot, disarm): the lifecycle's transitions."""
        if self.station is None:
            return self.unconfigured(response)
        want = ACTIVE if request.data else INACTIVE
        if self._state_id() != want:
            (self.trigger_activate if request.data else self.trigger_deactivate)()
        response.success = self._state_id() == want
        response.message = 'armed: transmitting' if request.data else 'disarmed: silent'
        return response

    def _on_start(self, request: Trigger.Request, response: Trigger.Response):
        if self.station is None:
            return self.unconfigured(response)
        response.success, response.message = self.station.start_trial(self._alive)
        return response

    def _on_stop(self, request: Trigger.Request, response: Trigger.Response):
        if self.station is None:
            return self.unconfigured(response)
        response.success, response.message = self.station.stop_trial()
        return response

    def _on_estop(self, request: Trigger.Request, response: Trigger.Response):
        if self.station is None:
            return self.unconfigured(response)
        self.station.emergency_stop()
        if self._state_id() == ACTIVE:  # disarmed: the lifecycle says so too
            self.trigger_deactivate()
        self._status(DiagnosticStatus.WARN, 'EMERGENCY STOP sent; bridge disarmed')
        response.success, response.message = True, 'emergency stop sent; bridge disarmed'
        return response

    def _on_check_servos(self, request: Trigger.Request, response: Trigger.Response):
        """HELLO: the robot answers VERSION and pings its servos (reports on servo_failures)."""
        if self.station is None:
            return self.unconfigured(response)
        ok, message = self.station.hello()
        response.success = ok
        response.message = (
            f'{message}; it checks its servos now (a dead one is reported on servo_failures)'
            if ok
            else message
        )
        return response

    def _on_get_servo_failures(self, request, response: GetServoFailures.Response):
        response.failures = list(self.failures.values())
        if self.station is None:
            response.check = int(ServoCheck.PENDING)
            response.check_status = f'bridge_node is {self.state_label()}: no link to the robot'
        else:
            check, response.check_status = self.station.servo_check(time.monotonic())
            response.check = int(check)
        return response

    def check_servos_soon(self) -> None:
        """HELLO in the background until the robot answers (it then checks every servo)."""
        station = self.station
        if station is None or self._checking.locked():
            return
        if station.servo_check(time.monotonic())[0] is ServoCheck.UNAVAILABLE:
            return  # the legacy firmware has no HELLO

        def check() -> None:
            with self._checking:
                for _ in range(SERVO_CHECK_TRIES):  # the port may still be opening
                    if self.station is not station or not station.armed:
                        return
                    ok, _message = station.hello()
                    if ok:
                        self.get_logger().info(
                            'the robot answered HELLO: it checks every servo (a dead one is'
                            ' reported on servo_failures)'
                        )
                        return
                    time.sleep(1.0)

        threading.Thread(target=check, name='servo_check', daemon=True).start()

    def _on_motor_power(self, request: SetBool.Request, response: SetBool.Response):
        """After an e-stop: ~/arm true, then ~/motor_power true, then upload and start trials."""
        if self.station is None:
            return self.unconfigured(response)
        op = self.station.motor_power(request.data)
        response.success, response.message = op.ok, op.message
        if op.ok:
            self._status(DiagnosticStatus.OK, op.message)
        return response

    # -- what the station hears ----------------------------------------------------------------
    def _link_status(self) -> LinkStatus:
        snap = self.station.snapshot(time.monotonic())
        msg = LinkStatus(port=str(self.station.config.port), **asdict(snap))
        msg.header.stamp = self.get_clock().now().to_msg()
        return msg

    def _on_connection(self, connected: bool, why: str) -> None:
        if not self._alive():  # shutting down: nobody left to tell
            return
        unless_closing(self, self.link_pub.publish, self._link_status())  # at once
        self.diagnostics.publish_now()
        if connected:
            self.get_logger().info(f'radio port {self.station.config.port} open')
            if self.station.armed:  # a robot that restarted checks its servos again
                self.check_servos_soon()
        else:
            self.get_logger().warning(f'radio link down: {why}')

    def _tick(self) -> None:
        unless_closing(self, self._tick_now)  # a tick at shutdown has nobody to tell

    def _tick_now(self) -> None:
        if self.station is None or not self._alive():
            return
        self.link_pub.publish(self._link_status())
        for kind, value in self.station.take_events():
            if kind == 'error':
                self._status(DiagnosticStatus.ERROR, f'robot reports: {value}')
            elif kind == 'servo_failure':
                self._on_servo_failure(value)
            elif kind == 'text':
                self._status(DiagnosticStatus.OK, f'robot says: {value}')
        result = self.station.finished_trial(time.monotonic())
        if result is not None:
            self._report_trial(result)

    def _report(self, report: Report) -> None:
        self._status(LEVELS[report.severity], report.text, **report.values)

    def _on_servo_failure(self, servo: int) -> None:
        r = servo_report(servo, self.station.config.leg_map)
        if r.leg is None:
            self.unknown_servo_reports += 1
            self.get_logger().warning(r.report.text)
            return
        msg = ServoFailure(servo_id=servo, robot_leg=r.robot_leg, leg=r.leg, joint=r.joint)
        msg.header.stamp = self.get_clock().now().to_msg()
        msg.header.frame_id = self.frames['base']
        self.failures.setdefault(servo, msg)  # held before it is told: a subscriber asks at once
        self.dead.setdefault(servo, time.monotonic())
        self.servo_pub.publish(msg)
        self.diagnostics.publish_now()  # its status turns ERROR at once
        self._report(r.report)

    def _report_trial(self, r: TrialResult) -> None:
        now = self.get_clock().now().to_msg()
        if r.valid:
            self.pose.add(r.x, r.y, r.yaw, max(r.walk, r.duration))
            odom = conv.trial_odometry(r, now, self.frames['odom'], self.frames['base'])
            self.trial_odom_pub.publish(odom)
        self.trial_result_pub.publish(conv.robot_trial(r, now, self.frames['odom']))
        self._report(trial_report(r, self.station.imu_port is not None))

    def _publish_state(self) -> None:
        unless_closing(self, self._publish_state_now)

    def _publish_state_now(self) -> None:
        if not self._alive():
            return
        trial = self.station.trial if self.station is not None else None
        walked = time.monotonic() - trial.start if trial is not None else None
        now = self.get_clock().now().to_msg()
        frames = self.frames['odom'], self.frames['base']
        odom = conv.continuous_odometry(self.pose, trial is not None, now, *frames)
        self.odom_pub.publish(odom)
        self.tf_pub.publish(TFMessage(transforms=[odom_transform(odom)]))
        positions = self.commanded.positions(walked)
        if positions is not None:
            msg = JointState(name=list(self.joint_names), position=[float(a) for a in positions])
            msg.header.stamp = now
            self.joints_pub.publish(msg)

    # the station's threads call these: at shutdown the context goes before they stop
    def _publish_imu(self, m) -> None:
        self.imu_last = time.monotonic()
        if self._alive():
            now = self.get_clock().now().to_msg()
            unless_closing(self, self.imu_pub.publish, conv.xsens_imu(m, now, self.frames['imu']))

    def _publish_attitude(self, t) -> None:
        self.imu_last = time.monotonic()
        if self._alive():
            now = self.get_clock().now().to_msg()
            msg = conv.attitude_imu(t, now, self.frames['base'])
            unless_closing(self, self.imu_pub.publish, msg)

    def shutdown(self) -> None:
        """Ctrl-C / SIGTERM: stop the robot and close the ports (called by run_node)."""
        self._halt()
        self._release()


def main(args: list[str] | None = None) -> int:
    """Entry point of ``ros2 run hexapod_bridge bridge_node``."""
    return run_node(BridgeNode, args, num_threads=4, parameters=PARAMETERS)


if __name__ == '__main__':
    sys.exit(main())
