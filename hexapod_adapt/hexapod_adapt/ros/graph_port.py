# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The ROS side of trials and recordings, shared by the nodes that walk the robot through the graph.

:class:`GraphPort` is :class:`hexapod_adapt.online.trials.TrialPort` over rclpy: it publishes
gaits, reads sim_node's trial stamps and the odometry, and calls sim_node's and bridge_node's
services. :class:`RecordedTopics` subscribes to what a run records beside its own messages (the
frames, joint states, IMU, foot contacts, and the latched URDF and static frames) and feeds a
:class:`hexapod_adapt.ros.run_recording.RunRecording`. The policies live in those library modules;
this module only converts messages.
"""

from __future__ import annotations

import math
from pathlib import Path
import time
from typing import Callable, Mapping

from diagnostic_msgs.msg import DiagnosticStatus
from hexapod_adapt.online.adaptation import TrialAborted
from hexapod_adapt.online.run_messages import duplicate_problem
from hexapod_adapt.online.trials import (
    OdomLog,
    OdomSample,
    RobotTrialResult,
    SampleLog,
    TiltLog,
    TiltSample,
    TrialLogs,
    Upload,
    WaitTimedOut,
)
from hexapod_adapt.ros.run_recording import RunRecording
from hexapod_gait import GaitParameters, standing_gait
from hexapod_gait.ros_conversions import gait_to_msg
from hexapod_msgs.msg import (
    AdaptationTrial,
    DamageDiagnosis,
    FootContacts,
    LegDamage,
    LinkStatus,
    RobotTrial,
    ServoFailure,
    TrajectoryActivation,
)
from hexapod_msgs.msg import GaitParameters as GaitParametersMsg
from hexapod_msgs.srv import GetLegDamage, UploadGait
from hexapod_sim.simulator import peak_tilt, quat_to_euler, upside_down
from hexapod_util.files import under_ros_home
from hexapod_util.recording import type_name
from hexapod_util.ros_glue import EVENTS, LATCHED, nodes_named, ODOM, SENSOR, TF_QOS, TRIALS
from nav_msgs.msg import Odometry
import numpy as np
from rcl_interfaces.msg import ParameterType
from rcl_interfaces.srv import GetParameters
import rclpy
from rclpy._rclpy_pybind11 import RCLError
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from rclpy.node import Node
from sensor_msgs.msg import Imu, JointState
from std_msgs.msg import Header, String
from std_srvs.srv import Trigger
from tf2_msgs.msg import TFMessage

#: Topics recorded while a run records, besides the node's own: a trial replays in 3D from them
#: (the simulator's foot contacts too), and the robot's servo reports are kept with it.
SENSOR_TOPICS = (
    (TFMessage, '/tf', TF_QOS),
    (JointState, 'joint_states', SENSOR),
    (Imu, 'imu/data', SENSOR),
    (FootContacts, 'foot_contacts', SENSOR),
    (ServoFailure, 'servo_failures', EVENTS),
)
#: Latched topics: the latest message of each opens every recording (waited for a while).
LATCHED_TOPICS = ((TFMessage, '/tf_static'), (String, 'robot_description'))
#: Latched topics a recording opens with when the graph has them, not waited for: bridge_node's
#: status on the robot (what the bridge last said, e.g. a gait it refused).
OPTIONAL_LATCHED_TOPICS = ((DiagnosticStatus, 'bridge/status'),)
#: bridge_node's link status older than this says nothing of the link [s] (it comes at 5 Hz).
LINK_STATUS_STALE_S = 2.0
#: The QoS each recorded topic is offered with in the graph (the recording's channel metadata, so
#: that ``ros2 bag play`` offers them again alike: the latched ones transient local).
RECORDED_QOS = {
    **{topic: qos for _, topic, qos in SENSOR_TOPICS},
    **{topic: LATCHED for _, topic in LATCHED_TOPICS + OPTIONAL_LATCHED_TOPICS},
    'odom': ODOM,
    'trial_odom': ODOM,
    'trial_result': TRIALS,
    'gait/parameters': LATCHED,
    'adapt/trials': TRIALS,
}
#: How long a recording waits at its start for the URDF and static frames (latched topics).
LATCHED_GRACE_S = 5.0
#: Every topic a run records, with its type: resolved when a recording starts.
RECORDED_TYPES = {
    topic: type_name(cls)
    for cls, topic in (
        *((cls, topic) for cls, topic, _ in SENSOR_TOPICS),
        *LATCHED_TOPICS,
        *OPTIONAL_LATCHED_TOPICS,
        (Odometry, 'odom'),
        (Odometry, 'trial_odom'),
        (RobotTrial, 'trial_result'),
        (GaitParametersMsg, 'gait/parameters'),
        (AdaptationTrial, 'adapt/trials'),
        (DamageDiagnosis, 'adapt/diagnosis'),
    )
}


def stamp_ns(stamp) -> int:
    """Nanoseconds of a builtin_interfaces/Time."""
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def odom_sample(msg: Odometry) -> OdomSample:
    """One odometry message as a trial reads it (received now)."""
    p, t, q = msg.pose.pose.position, msg.twist.twist.linear, msg.pose.pose.orientation
    quat = (q.x, q.y, q.z, q.w)
    return OdomSample(
        stamp_ns(msg.header.stamp), p.x, p.y, t.x, t.y, time.monotonic(),
        upside_down(quat), peak_tilt(np.array(quat)), quat_to_euler(quat),
    )  # fmt: skip


def qualified(node: Node, name: str) -> str:
    """Fully qualify a node name (relative names resolve in ``node``'s namespace)."""
    if name.startswith('/'):
        return name
    return f'{node.get_namespace().rstrip("/")}/{name}'


#: The name the graph gives a publisher whose node it has not discovered yet (rmw's placeholder).
UNKNOWN_NODE = '_NODE_NAME_UNKNOWN_'


def topic_publishers(node: Node, topic: str, wait_s: float = 2.0) -> list[str]:
    """Return the fully qualified names of ``topic``'s publishers (waits for unknown names)."""
    deadline = time.monotonic() + wait_s
    while True:
        infos = node.get_publishers_info_by_topic(topic)
        if time.monotonic() > deadline or all(i.node_name != UNKNOWN_NODE for i in infos):
            return [f'{i.node_namespace.rstrip("/")}/{i.node_name}' for i in infos]
        time.sleep(0.05)


def duplicate_peers(node: Node, peer: str) -> str:
    """Say why a run must stop: the node's or its peer's name is taken twice ('' if not)."""
    for name in (node.get_fully_qualified_name(), peer):
        problem = duplicate_problem(name, nodes_named(node, name))
        if problem:
            return problem
    return ''


class GraphPort:
    """
    Trials through gait_node + sim_node, or bridge_node, over rclpy: a :class:`TrialPort`.

    ``wait`` is the node's :meth:`Waiter.until` (a cancel or a shutdown ends every wait);
    ``odom`` and ``recording`` take what the port receives.
    """

    def __init__(
        self,
        node: Node,
        peers: tuple[str, str],
        wait: Callable[..., object],
        odom: OdomLog,
        recording: RunRecording,
    ) -> None:
        sim_name, bridge_name = peers
        self.node, self.wait, self.odom, self.recording = node, wait, odom, recording
        self.tilts = TiltLog(maxlen=2000)  # the robot's IMU attitude (robot trials' tip guard)
        self.trial_odom = OdomLog(maxlen=100)  # bridge_node's: one per valid robot trial
        # bridge_node's: one per robot trial, valid or not
        self.trial_results: SampleLog[RobotTrialResult] = SampleLog(maxlen=100)
        self.logs = TrialLogs(odom, self.trial_results, self.tilts)
        self._link: tuple[LinkStatus, float] | None = None  # the newest, when it came
        self.bridge_name = bridge_name
        self._active: int | None = None
        self._activations: dict[int, int] = {}  # trajectory stamp -> sim time it took effect
        self._reset: int | None = None
        self._last_stamp = 0
        sensors, work = MutuallyExclusiveCallbackGroup(), ReentrantCallbackGroup()
        self.gait_pub = node.create_publisher(GaitParametersMsg, 'gait/parameters', LATCHED)
        node.create_subscription(Odometry, 'odom', self._on_odom, ODOM, callback_group=sensors)
        node.create_subscription(
            Odometry, 'trial_odom', self._on_trial_odom, ODOM, callback_group=sensors
        )
        node.create_subscription(
            RobotTrial, 'trial_result', self._on_trial_result, TRIALS, callback_group=sensors
        )
        node.create_subscription(
            LinkStatus, f'{bridge_name}/link_status', self._on_link, 10, callback_group=sensors
        )
        node.create_subscription(Imu, 'imu/data', self._on_imu, SENSOR, callback_group=sensors)
        node.create_subscription(
            Header, 'sim/active_trajectory', self._on_active, LATCHED, callback_group=sensors
        )
        node.create_subscription(
            Header, 'sim/last_reset', self._on_reset, LATCHED, callback_group=sensors
        )
        node.create_subscription(
            TrajectoryActivation,
            'sim/activations',
            self._on_activation,
            EVENTS,
            callback_group=sensors,
        )
        self.reset_client = node.create_client(Trigger, f'{sim_name}/reset', callback_group=work)
        self.start_client = node.create_client(
            Trigger, f'{bridge_name}/start_trial', callback_group=work
        )
        self.stop_client = node.create_client(
            Trigger, f'{bridge_name}/stop_trial', callback_group=work
        )
        self.upload_client = node.create_client(
            UploadGait, f'{bridge_name}/upload_gait', callback_group=work
        )
        self.sim_params_client = node.create_client(
            GetParameters, f'{sim_name}/get_parameters', callback_group=work
        )
        self.damage_client = node.create_client(
            GetLegDamage, f'{sim_name}/get_damage', callback_group=work
        )
        self.bridge_params_client = node.create_client(
            GetParameters, f'{bridge_name}/get_parameters', callback_group=work
        )

    # -- inputs -----------------------------------------------------------------------------
    def _on_odom(self, msg: Odometry) -> None:
        self.odom.append(odom_sample(msg))
        self.recording.record('odom', msg)

    def _on_trial_odom(self, msg: Odometry) -> None:
        self.trial_odom.append(odom_sample(msg))
        self.recording.record('trial_odom', msg)

    def _on_trial_result(self, msg: RobotTrial) -> None:
        self.trial_results.append(
            RobotTrialResult(
                msg.valid, msg.retryable, msg.reason, msg.vx, msg.vy, time.monotonic()
            )
        )
        self.recording.record('trial_result', msg)

    def _on_link(self, msg: LinkStatus) -> None:
        self._link = (msg, time.monotonic())

    def link_heard(self) -> float:
        """Say when bridge_node's newest link status came (time.monotonic(); -inf: none yet)."""
        return -math.inf if self._link is None else self._link[1]

    def link_problem(self) -> str:
        """Say why bridge_node's radio link cannot carry a trial now ('' when it can)."""
        if self._link is None:
            return f'no link status from {self.bridge_name}/link_status yet (is bridge_node up?)'
        msg, received = self._link
        age = time.monotonic() - received
        if age > LINK_STATUS_STALE_S:
            return f'no link status from {self.bridge_name} for {age:.1f} s'
        if msg.up:
            return ''
        if not msg.connected:
            return f'the radio port is not open ({msg.last_error or msg.port})'
        return f'the robot has been silent for {msg.seconds_since_heard:.1f} s'

    def _on_imu(self, msg: Imu) -> None:
        q = msg.orientation
        quat = (q.x, q.y, q.z, q.w)
        sample = TiltSample(
            peak_tilt(np.array(quat)), time.monotonic(), quat_to_euler(quat),
            stamp_ns(msg.header.stamp),
        )  # fmt: skip
        self.tilts.append(sample)

    def _on_active(self, msg: Header) -> None:
        self._active = stamp_ns(msg.stamp)

    def _on_reset(self, msg: Header) -> None:
        self._reset = stamp_ns(msg.stamp)

    def _on_activation(self, msg: TrajectoryActivation) -> None:
        self._activations[stamp_ns(msg.trajectory)] = stamp_ns(msg.header.stamp)
        while len(self._activations) > 64:
            del self._activations[next(iter(self._activations))]

    # -- TrialPort --------------------------------------------------------------------------
    def active_stamp(self) -> int | None:
        """Stamp of the gait sim_node plays."""
        return self._active

    def activated_at(self, stamp: int) -> int | None:
        """Return the simulation time [ns] the gait ``stamp`` took effect (None: not yet)."""
        return self._activations.get(stamp)

    def reset_stamp(self) -> int | None:
        """Stamp of sim_node's latest reset."""
        return self._reset

    def gait_msg(self, gait: GaitParameters) -> GaitParametersMsg:
        """
        Return the message of ``gait``, stamped by the node's clock, made unique.

        sim_node echoes the stamp of the gait it plays: that echo is how a trial knows its gait is
        on.
        """
        msg = gait_to_msg(gait)
        self.stamp(msg)
        return msg

    def stamp(self, msg: GaitParametersMsg) -> int:
        """Stamp a gait message by the node's clock, later than any before; return the stamp."""
        stamp = max(self.node.get_clock().now().nanoseconds, self._last_stamp + 1)
        self._last_stamp = stamp
        msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(stamp, 1_000_000_000)
        return stamp

    def publish(self, msg: GaitParametersMsg) -> None:
        """Publish (and record) a gait on gait/parameters; TrialAborted once shutting down."""
        try:
            self.gait_pub.publish(msg)
        except RCLError:
            if rclpy.ok(context=self.node.context):
                raise
            raise TrialAborted('shutting down') from None
        self.recording.record('gait/parameters', msg)

    def publish_gait(self, gait: GaitParameters) -> tuple[int, float]:
        """Publish ``gait``: (its stamp [ns], its crab angle [rad])."""
        msg = self.gait_msg(gait)
        self.publish(msg)
        return stamp_ns(msg.header.stamp), msg.crab_angle

    def _service(self, client, timeout: float, what: str) -> None:
        """Wait for ``client``'s service (a cancel ends the wait); TrialAborted if it is absent."""
        try:
            self.wait(client.service_is_ready, timeout, f'service {client.srv_name}')
        except WaitTimedOut:
            raise TrialAborted(f'service {client.srv_name} is not available ({what})') from None

    def call(self, client, what: str, timeout: float = 10.0) -> Trigger.Response:
        """Call a Trigger service; TrialAborted if it is not there or does not answer."""
        self._service(client, timeout, what)
        future = client.call_async(Trigger.Request())
        self.wait(future.done, timeout, f'{client.srv_name} to answer')
        return future.result()

    def reset(self) -> tuple[bool, str]:
        """Reset the simulation (the damage stays)."""
        answer = self.call(self.reset_client, 'reset the simulation')
        return answer.success, answer.message

    def start_trial(self) -> tuple[bool, str]:
        """Start a trial on the robot."""
        answer = self.call(self.start_client, 'start the trial')
        return answer.success, answer.message

    def stop_trial(self) -> tuple[bool, str]:
        """Stop the robot's trial (it stands)."""
        answer = self.call(self.stop_client, 'stop the trial')
        return answer.success, answer.message

    def stand(self) -> None:
        """Publish the standing gait: the simulated robot stops walking where it is."""
        msg = gait_to_msg(standing_gait())
        self.stamp(msg)
        self.publish(msg)

    def upload_msg(self, msg: GaitParametersMsg, timeout: float) -> UploadGait.Response:
        """
        Upload through bridge_node's ~/upload_gait service.

        Only its typed answer confirms an upload (a status text, or any other publisher, cannot).
        """
        self._service(self.upload_client, min(timeout, 10.0), 'is bridge_node running?')
        future = self.upload_client.call_async(UploadGait.Request(gait=msg, timeout=timeout))
        self.wait(future.done, timeout + 5.0, 'bridge_node to upload the gait')
        return future.result()

    def upload(self, gait: GaitParameters, timeout: float) -> tuple[Upload, float]:
        """Upload ``gait``: (bridge_node's answer, its crab angle [rad])."""
        msg = self.gait_msg(gait)
        self.recording.record('gait/parameters', msg)
        answer = self.upload_msg(msg, timeout)
        upload = Upload(answer.success, answer.message, answer.archive_index, answer.answered)
        return upload, msg.crab_angle

    def leave_on(self, msg: GaitParametersMsg, timeout: float, upload: bool) -> str:
        """Leave the simulator (publish) or the robot (``upload``) on a gait; '' or why not."""
        if not upload:
            try:
                self.gait_pub.publish(msg)
            except RCLError:
                if rclpy.ok(context=self.node.context):
                    raise
                return 'shutting down'
            return ''
        try:
            answer = self.upload_msg(msg, timeout)
        except TrialAborted as exc:
            return str(exc)
        return '' if answer.success else answer.message

    def _ask(self, client, request, what: str, discover: float = 2.0, answer: float = 5.0):
        """
        Call ``client`` with ``request``; its response, or None if it is not there or silent.

        A cancel or a shutdown ends the wait (TrialAborted).
        """
        try:
            self.wait(client.service_is_ready, discover, f'service {client.srv_name}')
            future = client.call_async(request)
            self.wait(future.done, answer, what)
        except WaitTimedOut:
            return None
        return future.result()

    def sim_engine(self) -> str | None:
        """sim_node's ``engine`` parameter (None if it does not answer)."""
        response = self._ask(
            self.sim_params_client,
            GetParameters.Request(names=['engine']),
            "sim_node's parameters",
        )
        values = response.values if response is not None else []
        if values and values[0].type == ParameterType.PARAMETER_STRING:
            return values[0].string_value
        return None

    def sim_damage(self, timeout: float) -> LegDamage | None:
        """
        Ask sim_node for its damage now (GetLegDamage); None if it is not there or silent.

        The latched sim/damage topic may arrive after an ``adapt`` request that follows a
        SetLegFailure call at once; the service answers with what the simulator holds.
        """
        response = self._ask(
            self.damage_client,
            GetLegDamage.Request(),
            "sim_node's damage",
            discover=timeout,
            answer=timeout,
        )
        return response.damage if response is not None else None

    def bridge_trial(
        self, discover: float = 2.0, answer: float = 5.0
    ) -> tuple[float, float] | None:
        """
        Return bridge_node's (trial_duration, trial_settle) [s]: how it walks a robot trial.

        None if it is not found within ``discover`` s or does not answer within ``answer`` s.
        """
        response = self._ask(
            self.bridge_params_client,
            GetParameters.Request(names=['trial_duration', 'trial_settle']),
            "bridge_node's parameters",
            discover,
            answer,
        )
        values = response.values if response is not None else []
        if len(values) != 2 or any(v.type != ParameterType.PARAMETER_DOUBLE for v in values):
            return None
        return values[0].double_value, values[1].double_value


def trial_msg(trial, niche: int, best_niche: int, best_speed: float, archive) -> AdaptationTrial:
    """Return the AdaptationTrial of an M-BOA trial (stamp, gait and recording left to fill)."""
    msg = AdaptationTrial(trial=trial.number, archive_index=int(niche))
    msg.map_speed, msg.predicted_speed = trial.predicted, trial.gp_mean
    msg.predicted_speed_std, msg.measured_speed = trial.gp_std, trial.measured
    msg.tipped = trial.tipped
    msg.best_speed, msg.best_archive_index = best_speed, int(best_niche)
    msg.descriptor = [float(x) for x in archive.descriptors[niche]]
    return msg


class RecordedTopics:
    """Subscriptions that feed a run's recording: sensors while it records, latched always."""

    def __init__(self, node: Node, recording: RunRecording) -> None:
        self.node, self.recording = node, recording
        self.started_at = time.monotonic()  # discovery of the graph begins here
        group = MutuallyExclusiveCallbackGroup()
        for msg_type, topic, qos in SENSOR_TOPICS:
            node.create_subscription(
                msg_type,
                topic,
                lambda msg, topic=topic: recording.record(topic, msg),
                qos,
                callback_group=group,
            )
        latched = {
            topic: node.create_subscription(
                msg_type,
                topic,
                lambda msg, topic=topic: recording.on_latched(topic, msg),
                LATCHED,
                callback_group=group,
            )
            for msg_type, topic in LATCHED_TOPICS + OPTIONAL_LATCHED_TOPICS
        }
        # a run's recording waits for these (the optional ones open it only if they came)
        self.latched_subs = {topic: latched[topic] for _, topic in LATCHED_TOPICS}

    def await_latched(self, grace: float) -> list[str]:
        """
        Give the latched topics (URDF, static frames) ``grace`` s to arrive; return those missing.

        A publisher this node has not yet discovered (a loaded machine, a run asked for right after
        the node started) has delivered nothing. Topics with a publisher are waited for up to
        ``grace``; topics with none only for the first second of the run, or until this node has
        been up ``grace`` s. One that arrives later in the run is still recorded when it comes.
        """
        now = time.monotonic()
        deadline = now + grace
        discovery_deadline = min(deadline, max(now + 1.0, self.started_at + grace))

        def missing() -> list[str]:
            have = self.recording.latched_topics
            return [
                topic
                for topic, sub in self.latched_subs.items()
                if topic not in have
                and (sub.get_publisher_count() > 0 or time.monotonic() < discovery_deadline)
            ]

        while missing() and time.monotonic() < deadline and rclpy.ok(context=self.node.context):
            time.sleep(0.01)
        have = self.recording.latched_topics
        return [
            f'{topic} ({sub.get_publisher_count()} publishers seen)'
            for topic, sub in self.latched_subs.items()
            if topic not in have
        ]

    def start(
        self,
        directory: str,
        types: Mapping[str, str],
        warn: Callable[[str], None],
        prefix: str = 'adapt',
        grace: float = LATCHED_GRACE_S,
    ) -> Path | None:
        """
        Start a run's recording in ``directory``: the latched topics first, given ``grace`` s.

        Returns the file's path, or None when nothing can be recorded (the recording says why).
        """
        directory = str(under_ros_home(directory))  # as ROS 2 puts its logs
        left = self.await_latched(grace)
        if left:
            warn(
                f'recording starts without {", ".join(left)}: nothing received in {grace:g} s'
                ' (is a state publisher running?); it is recorded if it comes during the run'
            )
        return self.recording.start(directory, types, prefix=prefix, qos=RECORDED_QOS)
