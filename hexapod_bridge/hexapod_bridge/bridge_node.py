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
``ros2 run hexapod_bridge bridge_node``: the base station's link to the real hexapod.

Subscribes  gait/parameters   hexapod_msgs/GaitParameters (latched): uploaded to the robot
                              (gait-upload extension, acknowledged and retried)
Publishes   imu/data          sensor_msgs/Imu: from the Xsens on ``imu_port`` at its rate, or
                              the robot's 2 Hz attitude telemetry (orientation only)
            odom              nav_msgs/Odometry: one message per trial, the IMU estimate of the
                              displacement since the trial started (odom frame = the robot's
                              pose at the start), twist = mean velocity, covariances = the
                              estimate's stated accuracy
            ~/link_status     hexapod_msgs/LinkStatus at ``status_rate``
            bridge/status     diagnostic_msgs/DiagnosticStatus (latched): uploads, trials, errors
Services    ~/arm             std_srvs/SetBool: nothing is transmitted unless armed
            ~/upload_gait     hexapod_msgs/UploadGait: upload, answer when the robot acknowledged
            ~/start_trial     std_srvs/Trigger: walk the uploaded gait for ``trial_duration``
            ~/stop_trial      std_srvs/Trigger
            ~/emergency_stop  std_srvs/Trigger: always transmitted (armed or not), then disarms
            ~/motor_power     std_srvs/SetBool: servo power; on also clears a latched e-stop

After an emergency stop the robot refuses trials (ESTOPPED) until, in this order:
``~/arm true`` (the bridge transmits again), ``~/motor_power true`` (servos powered, e-stop
cleared), and a gait upload; then ``~/start_trial`` works again.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
import math
import sys
import threading
import time

from diagnostic_msgs.msg import DiagnosticStatus
from hexapod_bridge import legacy, xbus
from hexapod_bridge.extension import TrialState
from hexapod_bridge.link import Operation, RobotLink
from hexapod_bridge.odometry import TrialOdometry
from hexapod_bridge.serial_port import ReconnectingPort
from hexapod_description.tf_tree import quat_from_rpy
from hexapod_gait.parameters import GaitParameterError
from hexapod_gait.ros_conversions import gait_from_msg
from hexapod_gait.ros_glue import (
    declare,
    LATCHED,
    ODOM,
    odom_transform,
    ParamSpec,
    publish_status,
    run_node,
    SENSOR,
    TF_QOS,
)
from hexapod_msgs.msg import GaitParameters as GaitParametersMsg
from hexapod_msgs.msg import LinkStatus
from hexapod_msgs.srv import UploadGait
from nav_msgs.msg import Odometry
import rclpy
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.node import Node
from sensor_msgs.msg import Imu
from std_srvs.srv import SetBool, Trigger
from tf2_msgs.msg import TFMessage

#: Accuracy of the IMU trial-speed estimate, measured in test_bridge_odometry.py (docs/bridge.md).
SPEED_ACCURACY = 0.025  # m/s


@dataclass
class ActiveTrial:
    """The trial the bridge is measuring."""

    odometry: TrialOdometry
    start: float  # monotonic s when the start was sent
    crab: float  # walking direction of the gait [rad]
    duration: float  # s
    generation: int  # RobotLink.trial_generation once the robot acknowledged this start
    done_at: float | None = None


PARAMETERS = (
    ParamSpec(
        'port', '/tmp/hexapod_radio', 'Serial port of the 433 MHz radio module', read_only=True
    ),
    ParamSpec(
        'baud', 19200, 'Radio UART baud rate (the RF1100 modules run 19200 8N1)', read_only=True
    ),
    ParamSpec(
        'imu_port', '', "Serial port of an Xsens MTi wired to this PC ('' = none)", read_only=True
    ),
    ParamSpec('imu_baud', 115200, 'Xsens baud rate', read_only=True),
    ParamSpec(
        'firmware',
        'v2',
        "'v2' (gait-upload extension) or 'legacy' (today's firmware)",
        read_only=True,
    ),
    ParamSpec(
        'ping_period',
        1.0,
        'Keep-alive period [s]; the robot stops after ~27 s without pings',
        read_only=True,
        range=(0.1, 2.5),
    ),
    ParamSpec('trial_duration', 5.0, 'Walk duration of a trial [s]', range=(0.5, 60.0)),
    ParamSpec(
        'settle_time',
        0.5,
        'Rest after the walk before the odometry window closes [s]',
        read_only=True,
        range=(0.0, 10.0),
    ),
    ParamSpec(
        'pre_trial_buffer',
        0.3,
        'IMU history before a start command in the window [s]',
        read_only=True,
        range=(0.0, 5.0),
    ),
    ParamSpec(
        'imu_rate',
        100.0,
        "Xsens output rate [Hz] (its sample counter's clock)",
        read_only=True,
        range=(1.0, 1000.0),
    ),
    ParamSpec('odom_frame', 'odom', 'REP 105 odometry frame', read_only=True),
    ParamSpec('base_frame', 'base_link', 'Robot base frame', read_only=True),
    ParamSpec('imu_frame', 'imu_link', 'IMU frame', read_only=True),
    ParamSpec(
        'status_rate', 5.0, 'LinkStatus publish rate [Hz]', read_only=True, range=(0.1, 100.0)
    ),
    ParamSpec(
        'telemetry_period',
        0.5,
        'Robot attitude telemetry period requested on every (re)connect [s] '
        '(firmware default 0.5)',
        read_only=True,
        range=(0.05, 60.0),
    ),
    ParamSpec(
        'reconnect_max_backoff',
        0.25,
        'Longest wait between attempts to reopen a lost port [s]',
        read_only=True,
        range=(0.01, 5.0),
    ),
    ParamSpec('arm_on_start', False, 'Arm (allow transmission) at start-up', read_only=True),
    ParamSpec(
        'leg_map',
        [1, 2, 3, 4, 5, 6],
        "Robot's leg number for URDF legs 1..6 (a permutation); "
        '[1, 6, 5, 4, 3, 2] if the firmware keeps its clockwise numbering (unverified)',
        read_only=True,
    ),
)


class BridgeNode(Node):
    """The base station's link to the robot's radio and IMU (see the module docstring)."""

    def __init__(self, **kwargs) -> None:
        super().__init__('bridge_node', **kwargs)
        v = declare(self, PARAMETERS)
        self.port_path, baud, self.imu_path, imu_baud = (
            v['port'],
            v['baud'],
            v['imu_port'],
            v['imu_baud'],
        )
        firmware, ping_period, self.trial_duration = (
            v['firmware'],
            v['ping_period'],
            v['trial_duration'],
        )
        self.settle_time, self.pre_trial, self.imu_rate = (
            v['settle_time'],
            v['pre_trial_buffer'],
            v['imu_rate'],
        )
        self.odom_frame, self.base_frame, self.imu_frame = (
            v['odom_frame'],
            v['base_frame'],
            v['imu_frame'],
        )
        status_rate, self.telemetry_period = v['status_rate'], v['telemetry_period']
        backoff, arm, leg_map = v['reconnect_max_backoff'], v['arm_on_start'], v['leg_map']

        self.lock = threading.RLock()
        # a wrong firmware or leg map must not silently become the default: refuse to start
        self.link = RobotLink(
            baud=int(baud), ping_period=float(ping_period), firmware=str(firmware), leg_map=leg_map
        )
        self.radio = ReconnectingPort(str(self.port_path), int(baud), float(backoff))
        self.imu_port = (
            ReconnectingPort(str(self.imu_path), int(imu_baud), float(backoff))
            if self.imu_path
            else None
        )
        self._configured_connects = 0
        self._was_connected = False
        self.xbus = xbus.XbusParser()
        self.gait_id: int | None = None
        self.gait_crab = 0.0
        self.upload_op: Operation | None = None
        self.imu_history: deque = deque(maxlen=int(max(1, self.pre_trial * self.imu_rate)) + 1)
        self.trial: ActiveTrial | None = None
        self._counter_base = 0
        self._last_counter: int | None = None

        group = ReentrantCallbackGroup()
        self.imu_pub = self.create_publisher(Imu, 'imu/data', SENSOR)
        self.odom_pub = self.create_publisher(Odometry, 'odom', ODOM)
        self.tf_pub = self.create_publisher(TFMessage, '/tf', TF_QOS)
        self.link_pub = self.create_publisher(LinkStatus, '~/link_status', 10)
        self.status_pub = self.create_publisher(DiagnosticStatus, 'bridge/status', LATCHED)
        self.create_subscription(
            GaitParametersMsg, 'gait/parameters', self._on_gait, LATCHED, callback_group=group
        )
        self.create_service(SetBool, '~/arm', self._on_arm, callback_group=group)
        self.create_service(Trigger, '~/start_trial', self._on_start, callback_group=group)
        self.create_service(
            UploadGait, '~/upload_gait', self._on_upload_gait, callback_group=group
        )
        self.create_service(SetBool, '~/motor_power', self._on_motor_power, callback_group=group)
        self.create_service(Trigger, '~/stop_trial', self._on_stop, callback_group=group)
        self.create_service(Trigger, '~/emergency_stop', self._on_estop, callback_group=group)
        self.create_timer(
            1.0 / float(status_rate), self._publish_link_status, callback_group=group
        )
        if arm:
            self.link.arm(True, time.monotonic())

        self._running = True
        self._threads = [threading.Thread(target=self._radio_loop, name='radio', daemon=True)]
        if self.imu_port is not None:
            self._threads.append(threading.Thread(target=self._imu_loop, name='imu', daemon=True))
        for thread in self._threads:
            thread.start()
        self.get_logger().info(
            f'radio on {self.port_path} at {baud} baud, firmware {firmware}, '
            f'IMU {"on " + str(self.imu_path) if self.imu_path else "from robot telemetry"}; '
            f'{"armed" if arm else "disarmed (call ~/arm to transmit)"}'
        )

    # -- ROS callbacks ---------------------------------------------------------------------------
    def _status(self, level: bytes, message: str, **values) -> None:
        publish_status(self, self.status_pub, level, message, 'hexapod', **values)

    def _wait(self, op: Operation, timeout: float) -> bool:
        deadline = time.monotonic() + timeout
        while not op.done and time.monotonic() < deadline and rclpy.ok(context=self.context):
            time.sleep(0.005)
        return op.done

    def _on_gait(self, msg: GaitParametersMsg) -> None:
        try:
            gait = gait_from_msg(msg)
        except GaitParameterError as exc:
            self._status(DiagnosticStatus.ERROR, f'gait not uploaded: {exc}')
            return
        with self.lock:
            op = self.link.upload(gait)
            armed = self.link.armed
        if op.done and not op.ok:
            self._status(DiagnosticStatus.ERROR, f'gait not uploaded: {op.message}')
            return
        if not armed:
            self._status(
                DiagnosticStatus.WARN, 'gait queued; it is uploaded once the bridge is armed'
            )
        self.upload_op = op
        threading.Thread(target=self._finish_upload, args=(op, gait), daemon=True).start()

    def _finish_upload(self, op: Operation, gait) -> None:
        while not op.done and self._running:
            time.sleep(0.01)
        if op.ok:
            with self.lock:
                self.gait_id, self.gait_crab = op.result['gait_id'], gait.crab_angle
            self._status(
                DiagnosticStatus.OK,
                f'gait uploaded (archive index {gait.archive_index})',
                gait_id=op.result['gait_id'],
                archive_index=gait.archive_index,
            )
        elif self._running:
            self._status(DiagnosticStatus.ERROR, f'gait upload failed: {op.message}')

    def _on_upload_gait(self, request: UploadGait.Request, response: UploadGait.Response):
        """
        Upload and answer once the robot acknowledged (or refused) it.

        The typed contract for trials (status texts are for people).
        """
        response.archive_index = request.gait.archive_index
        timeout = (
            request.timeout
            if math.isfinite(request.timeout) and 0 < request.timeout <= 600
            else 30.0
        )
        try:
            gait = gait_from_msg(request.gait)
        except GaitParameterError as exc:
            response.success, response.message = False, f'gait not uploaded: {exc}'
            return response
        with self.lock:
            if not self.link.armed:
                response.success, response.message = False, 'not armed: call ~/arm first'
                return response
            op = self.link.upload(gait)
        if not self._wait(op, timeout):
            response.success, response.message = (
                False,
                f'gait not uploaded: no answer in {timeout:g} s',
            )
            return response
        if not op.ok:
            response.success, response.message = False, f'gait not uploaded: {op.message}'
            self._status(DiagnosticStatus.ERROR, response.message)
            return response
        with self.lock:
            self.gait_id, self.gait_crab = op.result['gait_id'], gait.crab_angle
        response.success, response.gait_id = True, int(op.result['gait_id'])
        response.message = f'gait uploaded as robot gait {response.gait_id}'
        self._status(
            DiagnosticStatus.OK,
            f'{response.message} (archive index {gait.archive_index})',
            gait_id=response.gait_id,
            archive_index=gait.archive_index,
        )
        return response

    def _on_arm(self, request: SetBool.Request, response: SetBool.Response):
        with self.lock:
            self.link.arm(request.data, time.monotonic())
        response.success, response.message = (
            True,
            'armed: transmitting' if request.data else 'disarmed: silent',
        )
        return response

    def _on_start(self, request: Trigger.Request, response: Trigger.Response):
        with self.lock:
            if not self.link.armed:
                response.success, response.message = False, 'not armed: call ~/arm first'
                return response
            if self.link.firmware == 'v2' and self.gait_id is None:
                response.success, response.message = (
                    False,
                    'no gait uploaded yet: publish gait/parameters first',
                )
                return response
            if self.trial is not None:
                response.success, response.message = False, 'a trial is already running'
                return response
            odometry = TrialOdometry()
            for sample in self.imu_history:
                odometry.add(*sample)
            op = self.link.start_trial(self.trial_duration, self.gait_id or 0)
            self.trial = ActiveTrial(
                odometry,
                time.monotonic(),
                self.gait_crab,
                self.trial_duration,
                generation=self.link.trial_generation + 1,
            )
        if not self._wait(op, 3.0) or not op.ok:
            with self.lock:
                self.trial = None
            response.success = False
            response.message = (
                f'robot did not start the trial: {op.message or "no acknowledgement"}'
            )
            return response
        response.success = True
        response.message = f'trial started: gait {self.gait_id}, {self.trial_duration:g} s'
        return response

    def _on_stop(self, request: Trigger.Request, response: Trigger.Response):
        with self.lock:
            op = self.link.stop_trial()
        ok = self._wait(op, 3.0) and op.ok
        response.success, response.message = ok, op.message or 'no acknowledgement'
        return response

    def _on_estop(self, request: Trigger.Request, response: Trigger.Response):
        with self.lock:
            self.link.emergency_stop()
            self.link.arm(False, time.monotonic())
        self._status(DiagnosticStatus.WARN, 'EMERGENCY STOP sent; bridge disarmed')
        response.success, response.message = True, 'emergency stop sent; bridge disarmed'
        return response

    def _on_motor_power(self, request: SetBool.Request, response: SetBool.Response):
        """After an e-stop: ~/arm true, then ~/motor_power true, then upload and start trials."""
        with self.lock:
            op = self.link.motor_power(request.data)
        response.success, response.message = op.ok, op.message
        if op.ok:
            self._status(DiagnosticStatus.OK, op.message)
        return response

    def _link_status(self, now: float) -> LinkStatus:
        with self.lock:
            s, p = self.link.stats, self.link.parser.stats
            msg = LinkStatus(
                connected=self.radio.connected,
                armed=self.link.armed,
                seconds_since_heard=(
                    (now - self.link.last_heard)
                    if math.isfinite(self.link.last_heard)
                    else math.inf
                ),
                frames_ok=p.frames_ok,
                checksum_errors=p.checksum_errors + p.implausible,
                resyncs=p.resyncs,
                bytes_dropped=p.bytes_dropped,
                frames_sent=s.frames_sent,
                retries=s.retries,
                port=str(self.port_path),
                last_error=self.radio.last_error,
            )
        msg.header.stamp = self.get_clock().now().to_msg()
        return msg

    def _publish_link_status(self) -> None:
        now = time.monotonic()
        self.link_pub.publish(self._link_status(now))
        with self.lock:
            events = []
            while self.link.events:
                events.append(self.link.events.popleft())
        for kind, value in events:
            if kind == 'error':
                self._status(DiagnosticStatus.ERROR, f'robot reports: {value}')
            elif kind == 'text':
                self._status(DiagnosticStatus.OK, f'robot says: {value}')
        self._check_trial(now)

    # -- I/O threads ---------------------------------------------------------------------------
    def _guarded(self, body, name: str) -> None:
        """
        Run a thread's loop body forever.

        An unexpected error is logged (once per kind) and the loop goes on; it ends quietly when
        the node shuts down.
        """
        seen: set[type] = set()
        while self._running:
            try:
                body()
            except Exception as exc:  # keep the link alive whatever one iteration hit
                if not self._running or not rclpy.ok(context=self.context):
                    return
                key = type(exc)
                if key not in seen:
                    seen.add(key)
                    self.get_logger().error(f'{name} thread: {exc!r} (continuing)')
                time.sleep(0.01)

    def _radio_loop(self) -> None:
        self._guarded(self._radio_once, 'radio')

    def _imu_loop(self) -> None:
        self._guarded(self._imu_once, 'imu')

    def _radio_once(self) -> None:
        """
        One turn of the radio thread.

        (re)open, read, hand bytes to the link, write what it schedules.
        """
        now = time.monotonic()
        self._report_connection_change()
        if not self.radio.ensure_open(now):
            time.sleep(0.02)
            return
        self._report_connection_change()
        data = self.radio.read(0.005)
        now = time.monotonic()
        with self.lock:
            if self.radio.connects != self._configured_connects:
                self._configured_connects = self.radio.connects
                self.link.set_telemetry_period(float(self.telemetry_period))
            frames = self.link.receive(data, now) if data else []
            out = self.link.poll(now)
        for frame in out:
            if not self.radio.write(frame):
                break
        for frame in frames:
            if isinstance(frame, legacy.Telemetry) and self.imu_port is None:
                self._publish_attitude(frame)

    def _report_connection_change(self) -> None:
        """Publish LinkStatus at once (not at the next 5 Hz tick) when the port goes or comes."""
        connected = self.radio.connected
        if connected == self._was_connected:
            return
        self._was_connected = connected
        self.link_pub.publish(self._link_status(time.monotonic()))
        if connected:
            self.get_logger().info(f'radio port {self.port_path} open')
        else:
            self.get_logger().warning(f'radio link down: {self.radio.last_error}')

    def _imu_once(self) -> None:
        assert self.imu_port is not None
        now = time.monotonic()
        if not self.imu_port.ensure_open(now):
            time.sleep(0.02)
            return
        if self.imu_port.connects and self._last_counter is None:
            self.imu_port.write(xbus.GO_TO_MEASUREMENT)
        data = self.imu_port.read(0.01)
        for message in self.xbus.feed(data) if data else []:
            if isinstance(message, xbus.MTData):
                self._on_mtdata(message)

    def _on_mtdata(self, m: xbus.MTData) -> None:
        # unwrap the uint16 sample counter into a monotonic IMU clock
        if self._last_counter is not None and m.counter < self._last_counter:
            self._counter_base += 0x10000
        self._last_counter = m.counter
        t = (self._counter_base + m.counter) / self.imu_rate
        sample = (t, m.acc, m.euler)
        with self.lock:
            self.imu_history.append(sample)
            if self.trial is not None:
                self.trial.odometry.add(*sample)
        msg = Imu()
        msg.header.stamp = self.get_clock().now().to_msg()
        msg.header.frame_id = str(self.imu_frame)
        q = quat_from_rpy(*(math.radians(v) for v in m.euler))
        msg.orientation.x, msg.orientation.y, msg.orientation.z, msg.orientation.w = q
        msg.angular_velocity.x, msg.angular_velocity.y, msg.angular_velocity.z = (
            float(v) for v in m.gyr
        )
        msg.linear_acceleration.x, msg.linear_acceleration.y, msg.linear_acceleration.z = (
            float(v) for v in m.acc
        )
        self.imu_pub.publish(msg)

    def _publish_attitude(self, t) -> None:
        msg = Imu()
        msg.header.stamp = self.get_clock().now().to_msg()
        msg.header.frame_id = str(self.base_frame)
        q = quat_from_rpy(t.roll, t.pitch, t.yaw)
        msg.orientation.x, msg.orientation.y, msg.orientation.z, msg.orientation.w = q
        msg.angular_velocity_covariance[0] = -1.0  # not provided by the telemetry
        msg.linear_acceleration_covariance[0] = -1.0
        self.imu_pub.publish(msg)

    def _check_trial(self, now: float) -> None:
        with self.lock:
            trial = self.trial
            if trial is None:
                return
            # only the robot's reports about THIS trial (acknowledged start) can end it
            ours = self.link.trial_generation == trial.generation
            finished = ours and self.link.trial_state in (
                TrialState.DONE,
                TrialState.STOPPED,
                TrialState.FAILSAFE,
                TrialState.ESTOPPED,
            )
            overdue = now - trial.start > trial.duration + 3.0
            if trial.done_at is None and (finished or overdue):
                trial.done_at = now
            if trial.done_at is None or now - trial.done_at < self.settle_time:
                return
            self.trial = None
            state = self.link.trial_state.name if ours else 'NO_REPORT'
        if self.imu_port is None:
            self._status(
                DiagnosticStatus.WARN,
                'trial finished; no IMU configured: enter the measured distance '
                "by hand (adapt node's distance entry)",
                state=state,
            )
            return
        try:
            est = trial.odometry.estimate(trial.crab, trial.duration)
        except ValueError as exc:
            self._status(
                DiagnosticStatus.ERROR, f'trial finished but no odometry: {exc}', state=state
            )
            return
        if not (math.isfinite(est.speed) and math.isfinite(est.distance)):
            self._status(
                DiagnosticStatus.ERROR,
                'trial finished but the IMU estimate is not finite '
                f'(speed {est.speed!r} m/s): no odometry published',
                state=state,
            )
            return
        self._publish_odometry(est, trial)
        self._status(
            DiagnosticStatus.OK,
            f'trial {state.lower()}: {est.distance:.3f} m, {est.speed:.3f} m/s '
            f'(IMU estimate, +/-{SPEED_ACCURACY} m/s)',
            distance=f'{est.distance:.4f}',
            speed=f'{est.speed:.4f}',
            samples=est.samples,
            drift_removed=f'{est.drift_velocity:.3f}',
            state=state,
        )

    def _publish_odometry(self, est, trial) -> None:
        yaw0 = trial.odometry.yaw0 or 0.0
        c, s = math.cos(-yaw0), math.sin(-yaw0)
        x = c * est.displacement[0] - s * est.displacement[1]
        y = s * est.displacement[0] + c * est.displacement[1]
        odom = Odometry()
        odom.header.stamp = self.get_clock().now().to_msg()
        odom.header.frame_id, odom.child_frame_id = str(self.odom_frame), str(self.base_frame)
        odom.pose.pose.position.x, odom.pose.pose.position.y = float(x), float(y)
        odom.pose.pose.orientation.w = 1.0
        odom.twist.twist.linear.x, odom.twist.twist.linear.y = (
            x / trial.duration,
            y / trial.duration,
        )
        var_pos = (SPEED_ACCURACY * trial.duration) ** 2
        odom.pose.covariance[0] = odom.pose.covariance[7] = var_pos
        odom.twist.covariance[0] = odom.twist.covariance[7] = SPEED_ACCURACY**2
        self.odom_pub.publish(odom)
        self.tf_pub.publish(TFMessage(transforms=[odom_transform(odom)]))

    def shutdown(self) -> None:
        """Stop the I/O threads and close the ports (called by run_node)."""
        self._running = False
        for thread in self._threads:
            thread.join(timeout=2.0)
        self.radio.close()
        if self.imu_port is not None:
            self.imu_port.close()


def reports_down_since(status: LinkStatus, wall_time: float) -> bool:
    """Return True if ``status`` says "not connected" and was stamped after ``wall_time`` [s]."""
    stamp = status.header.stamp.sec + status.header.stamp.nanosec * 1e-9
    return not status.connected and stamp > wall_time


def main(args: list[str] | None = None) -> int:
    """Entry point of ``ros2 run hexapod_bridge bridge_node``."""
    return run_node(BridgeNode, args, num_threads=4, parameters=PARAMETERS)


if __name__ == '__main__':
    sys.exit(main())
