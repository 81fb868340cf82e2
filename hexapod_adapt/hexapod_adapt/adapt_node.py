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
``ros2 run hexapod_adapt adapt_node``: Intelligent Trial & Error on the simulator or the robot.

Loads an archive (``archive`` parameter, by default the shipped default map; refused, with the
reason, if its genotype mapping -- and in ``sim`` mode its URDF and trial duration -- differ from
this installation's) and runs M-BOA when its ``adapt`` service is called. Each trial publishes the
gait on ``gait/parameters`` and measures its speed along the walking direction:

  mode ``sim``     through gait_node + sim_node: wait until sim_node plays the gait
                   (``sim/active_trajectory`` carries the gait's stamp), call ``<sim>/reset``,
                   then take ``odom`` at exactly reset + trial_duration of sim time;
  mode ``robot``   through bridge_node: wait for "gait uploaded" on ``bridge/status``, call
                   ``<bridge>/start_trial``, take the trial's ``odom`` message (IMU estimate);
  mode ``manual``  the robot walks (uploaded by bridge_node) and the operator reports the
                   tape-measured distance with ``~/report_distance``.

Publishes ``adapt/trials`` (AdaptationTrial) per trial and records each run (trials, gaits,
odometry) to an MCAP file in ``record_dir``. Services: ``adapt`` (hexapod_msgs/Adapt),
``~/report_distance`` (hexapod_msgs/ReportDistance), ``~/cancel`` (std_srvs/Trigger).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
import math
import os
from pathlib import Path
import sys
import threading
import time
import traceback

from hexapod_adapt.adaptation import adapt, TrialAborted
from hexapod_adapt.archive import Archive, ArchiveError, compatibility_problems, load_archive
from hexapod_adapt.maps import DEFAULT_MAP, shipped_map
from hexapod_adapt.mboa import (
    ALPHA_RANGE,
    KAPPA_RANGE,
    LENGTH_SCALE_RANGE,
    MAX_TRIALS_LIMIT,
    MboaConfig,
    NOISE_RANGE,
)
from hexapod_adapt.recording import create_recording, McapRecorder, RecordingClosed
from hexapod_adapt.simulation import archive_engine, simulation_fingerprint
from hexapod_gait import from_genotype
from hexapod_gait.ros_conversions import gait_to_msg
from hexapod_gait.ros_glue import (
    declare,
    LATCHED,
    nodes_named,
    ODOM,
    ParamSpec,
    run_node,
    SENSOR,
    TF_QOS,
    watch_for_duplicates,
)
from hexapod_msgs.msg import AdaptationTrial, FootContacts
from hexapod_msgs.msg import GaitParameters as GaitParametersMsg
from hexapod_msgs.srv import Adapt, ReportDistance, UploadGait
from nav_msgs.msg import Odometry
from rcl_interfaces.msg import ParameterType, SetParametersResult
from rcl_interfaces.srv import GetParameters
import rclpy
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from rclpy.node import Node
from sensor_msgs.msg import Imu, JointState
from std_msgs.msg import Header, String
from std_srvs.srv import Trigger
from tf2_msgs.msg import TFMessage

MODES = ('sim', 'robot', 'manual')


@dataclass(frozen=True)
class OdomSample:
    """One odometry message as a trial reads it."""

    stamp_ns: int  # header stamp
    x: float  # position in the odom frame [m]
    y: float
    vx: float  # twist (the bridge's trial-mean velocity) [m/s]
    vy: float
    received: float  # time.monotonic() when it arrived


def _ns(stamp) -> int:
    return stamp.sec * 1_000_000_000 + stamp.nanosec


RUN_SETTINGS = ('max_trials', 'trial_duration', 'alpha', 'kappa', 'length_scale', 'noise')


#: How long a recorded run waits at its start for the URDF and static frames (latched topics).
LATCHED_GRACE_S = 5.0

#: A trial must cover at least one gait cycle of the controller's default 1 s period.
TRIAL_DURATION_RANGE = (1.0, 120.0)


def run_settings(values: dict) -> tuple[MboaConfig, float]:
    """
    (M-BOA configuration, trial duration [s]) from the six run settings.

    ValueError says which is out of range and what the range is.
    """
    duration = float(values['trial_duration'])
    low, high = TRIAL_DURATION_RANGE
    if not (math.isfinite(duration) and low <= duration <= high):
        raise ValueError(f'trial_duration must be in [{low:g}, {high:g}] s, got {duration!r}')
    config = MboaConfig(
        max_trials=int(values['max_trials']),
        alpha=float(values['alpha']),
        kappa=float(values['kappa']),
        length_scale=float(values['length_scale']),
        noise=float(values['noise']),
    )
    return config, duration


def expected_metadata(mode: str) -> dict:
    """
    Return what an archive must match to be used in ``mode``: the gait mapping always.

    The URDF and trial duration too when trials run on the simulator. The engine that made the map
    need not be the trials' engine: that is a reality gap, which M-BOA exists to cross (see
    :func:`engine_note`).
    """
    fp = simulation_fingerprint()
    if mode != 'sim':
        return {'genotype_mapping': fp['genotype_mapping']}
    return {key: fp[key] for key in ('genotype_mapping', 'urdf_sha256', 'trial_duration')}


def engine_note(archive: Archive, trial_engine: str | None) -> str:
    """Say when the map was made on another engine than the trials run on ('' if not)."""
    made_on = archive_engine(archive.metadata) or 'an unrecorded engine'
    if trial_engine is None or made_on == trial_engine:
        return ''
    return f'map made on {made_on}, trials on {trial_engine}: adapting across that gap'


PARAMETERS = (
    ParamSpec(
        'archive',
        '',
        "Archive file (.npz from generate_map; '' = the shipped default map); may be changed at "
        'run time, a file that fails to load is refused and the last good one kept',
    ),
    ParamSpec('mode', 'sim', 'Trials on: sim | robot | manual', read_only=True),
    ParamSpec('max_trials', 20, 'Default maximum trials per run', range=(1, MAX_TRIALS_LIMIT)),
    ParamSpec('trial_duration', 5.0, 'Default trial duration [s]', range=TRIAL_DURATION_RANGE),
    ParamSpec(
        'alpha',
        0.9,
        'Default stop ratio: stop when the best measured speed reaches alpha x the highest '
        'predicted one',
        range=ALPHA_RANGE,
    ),
    ParamSpec('kappa', 0.05, 'Default UCB weight on the posterior std', range=KAPPA_RANGE),
    ParamSpec(
        'length_scale',
        0.4,
        'Default Matern length scale rho [descriptor units]',
        range=LENGTH_SCALE_RANGE,
    ),
    ParamSpec('noise', 0.001, 'Default observation noise variance [(m/s)^2]', range=NOISE_RANGE),
    ParamSpec('record_dir', 'adaptation_runs', "MCAP files go here ('' = no recording)"),
    ParamSpec('sim_node', 'sim_node', 'Name of the simulator node (mode sim)', read_only=True),
    ParamSpec(
        'bridge_node',
        'bridge_node',
        'Name of the bridge node (modes robot, manual)',
        read_only=True,
    ),
    ParamSpec('trial_timeout', 120.0, 'Wall-clock limit for one trial [s]', range=(1.0, 3600.0)),
    ParamSpec(
        'stand_still',
        1.0,
        'Robot modes: seconds the robot stands still before each trial (clean '
        'zero-velocity IMU window) [s]',
        range=(0.0, 60.0),
    ),
)


class AdaptNode(Node):
    """Run M-BOA over an archive when its ``adapt`` service is called."""

    def __init__(self) -> None:
        super().__init__('adapt_node')
        self.started_at = time.monotonic()  # discovery of the graph begins here
        declare(self, PARAMETERS)
        self.mode = self.get_parameter('mode').value
        self.archive: Archive | None = None
        self.archive_problem = "no archive loaded: set the 'archive' parameter"
        if self.mode not in MODES:
            # read-only parameter: the node runs, refusing every request with the reason
            self.archive_problem = (
                f'parameter mode must be one of {", ".join(MODES)}, got {self.mode!r}; restart the'
                ' node'
            )
            self.get_logger().error(self.archive_problem)
        else:
            self._load_archive(self.get_parameter('archive').value)
        self.add_on_set_parameters_callback(self._on_set_parameters)

        self.busy = threading.Lock()
        self.cancel_requested = False
        self.data_lock = threading.Lock()
        self.odom: deque[OdomSample] = deque(maxlen=20000)
        self.active_stamp = None
        self.reset_stamp = None
        self._last_gait_stamp = 0
        self.reported: list[float] = []
        self.recorder: McapRecorder | None = None

        sensors = MutuallyExclusiveCallbackGroup()
        work = ReentrantCallbackGroup()
        self.gait_pub = self.create_publisher(GaitParametersMsg, 'gait/parameters', LATCHED)
        self.trial_pub = self.create_publisher(AdaptationTrial, 'adapt/trials', 10)
        self.create_subscription(Odometry, 'odom', self._on_odom, ODOM, callback_group=sensors)
        self.create_subscription(
            Header, 'sim/active_trajectory', self._on_active, LATCHED, callback_group=sensors
        )
        self.create_subscription(
            Header, 'sim/last_reset', self._on_reset, LATCHED, callback_group=sensors
        )
        # recorded while a run records, so that a trial replays in Foxglove's 3D panel
        recorded = MutuallyExclusiveCallbackGroup()
        for msg_type, topic, qos in (
            (TFMessage, '/tf', TF_QOS),
            (JointState, 'joint_states', SENSOR),
            (Imu, 'imu/data', SENSOR),
            (FootContacts, 'foot_contacts', SENSOR),
        ):
            self.create_subscription(
                msg_type,
                topic,
                lambda msg, topic=topic: self._record(topic, msg),
                qos,
                callback_group=recorded,
            )
        # latest latched message of each topic, recorded at a start
        self._latched: dict[str, object] = {}
        self._latched_lock = threading.Lock()  # a recording starts with every latched message
        self._latched_subs = {}
        for msg_type, topic in ((TFMessage, '/tf_static'), (String, 'robot_description')):
            self._latched_subs[topic] = self.create_subscription(
                msg_type,
                topic,
                lambda msg, topic=topic: self._on_latched(topic, msg),
                LATCHED,
                callback_group=recorded,
            )
        sim_name = self.get_parameter('sim_node').value
        bridge_name = self.get_parameter('bridge_node').value
        self.sim_name, self.bridge_name = self._qualified(sim_name), self._qualified(bridge_name)
        self.reset_client = self.create_client(Trigger, f'{sim_name}/reset', callback_group=work)
        self.start_client = self.create_client(
            Trigger, f'{bridge_name}/start_trial', callback_group=work
        )
        self.upload_client = self.create_client(
            UploadGait, f'{bridge_name}/upload_gait', callback_group=work
        )
        self.sim_params_client = self.create_client(
            GetParameters, f'{sim_name}/get_parameters', callback_group=work
        )
        self.create_service(Adapt, 'adapt', self._on_adapt, callback_group=work)
        self.create_service(
            ReportDistance, '~/report_distance', self._on_report, callback_group=work
        )
        self.create_service(Trigger, '~/cancel', self._on_cancel, callback_group=work)
        watch_for_duplicates(self, self.get_logger().error)
        self.get_logger().info(
            f'adapt_node ready: mode {self.mode}; '
            + (f'archive {self.archive.n_filled} gaits' if self.archive else self.archive_problem)
        )

    def _qualified(self, name: str) -> str:
        """Fully qualify a node name (relative names resolve in this node's namespace)."""
        if name.startswith('/'):
            return name
        namespace = self.get_namespace().rstrip('/')
        return f'{namespace}/{name}'

    def shutdown(self) -> None:
        """Ctrl-C / SIGTERM mid-run: finish the MCAP file (called by run_node)."""
        recorder = self.recorder
        if recorder is not None:
            recorder.close()

    # -- archive ----------------------------------------------------------------------------
    @staticmethod
    def _archive_path(value: str) -> str:
        """Return the file the ``archive`` parameter names ('' = the shipped default map)."""
        return os.path.expanduser(value) if value else str(shipped_map(DEFAULT_MAP))

    def _try_load(self, path: str) -> tuple[Archive | None, str]:
        try:
            archive = load_archive(path)
        except ArchiveError as exc:
            return None, str(exc)
        problems = compatibility_problems(archive, expected_metadata(self.mode))
        if problems:
            return None, f'{path} does not fit this installation: ' + '; '.join(problems)
        if archive.n_filled == 0:
            return None, f'{path} has no gaits'
        return archive, ''

    def _load_archive(self, value: str) -> None:
        path = self._archive_path(value)
        archive, problem = self._try_load(path)
        if archive is None:
            self.archive_problem = problem
            self.get_logger().error(problem)
        else:
            self.archive, self.archive_problem = archive, ''
            self.get_logger().info(
                f'archive {path}: {archive.n_filled} gaits in {archive.n_niches} niches'
            )

    def _on_set_parameters(self, params) -> SetParametersResult:
        for param in params:
            if param.name == 'archive':
                if self.mode not in MODES:
                    return SetParametersResult(successful=False, reason=self.archive_problem)
                if self.busy.locked():
                    return SetParametersResult(successful=False, reason='an adaptation is running')
                archive, problem = self._try_load(self._archive_path(param.value))
                if archive is None:
                    # the old archive stays
                    return SetParametersResult(successful=False, reason=problem)
                self.archive, self.archive_problem = archive, ''
            elif param.name == 'trial_timeout' and param.value <= 0:
                return SetParametersResult(successful=False, reason='trial_timeout must be > 0')
        # the run defaults are checked by the same rules as a request's fields
        values = {name: self.get_parameter(name).value for name in RUN_SETTINGS}
        values.update({param.name: param.value for param in params if param.name in RUN_SETTINGS})
        try:
            run_settings(values)
        except (TypeError, ValueError) as exc:
            return SetParametersResult(successful=False, reason=str(exc))
        return SetParametersResult(successful=True)

    # -- inputs -----------------------------------------------------------------------------
    def _on_odom(self, msg: Odometry) -> None:
        p, t = msg.pose.pose.position, msg.twist.twist.linear
        with self.data_lock:
            self.odom.append(
                OdomSample(_ns(msg.header.stamp), p.x, p.y, t.x, t.y, time.monotonic())
            )
        if self.recorder is not None:
            self._record('odom', msg)

    def _on_latched(self, topic: str, msg) -> None:
        with self._latched_lock:
            self._latched[topic] = msg
            self._record(topic, msg)

    def _on_active(self, msg: Header) -> None:
        self.active_stamp = _ns(msg.stamp)

    def _on_reset(self, msg: Header) -> None:
        self.reset_stamp = _ns(msg.stamp)

    def _on_report(self, request: ReportDistance.Request, response: ReportDistance.Response):
        if not math.isfinite(request.distance) or abs(request.distance) > 50.0:
            response.accepted, response.message = (
                False,
                f'distance {request.distance!r} m is not a plausible trial distance',
            )
        elif self.mode != 'manual' or not self.busy.locked():
            response.accepted, response.message = (
                False,
                'no manual trial is waiting for a distance',
            )
        else:
            self.reported.append(float(request.distance))
            response.accepted, response.message = True, f'{request.distance:.3f} m recorded'
        return response

    def _on_cancel(self, request, response):
        running = self.busy.locked()
        self.cancel_requested = running
        response.success = running
        response.message = (
            'cancelling after the current trial' if running else 'no adaptation is running'
        )
        return response

    # -- helpers ----------------------------------------------------------------------------
    def _write(self, recorder: McapRecorder, topic: str, msg) -> None:
        """
        Write ``msg`` to ``recorder`` under the fully qualified name of ``topic``, at node time.

        Relative names resolve in this node's namespace, as its publishers and subscribers do.
        """
        recorder.record(
            self.resolve_topic_name(topic), msg, log_time_ns=self.get_clock().now().nanoseconds
        )

    def _record(self, topic: str, msg) -> None:
        """Record ``msg`` in this run's recording, if one is open; a failure stops recording."""
        recorder = self.recorder
        if recorder is not None:
            try:
                self._write(recorder, topic, msg)
            except RecordingClosed:
                pass  # a sensor message that came as the run ended: the run's file is complete
            except (OSError, RuntimeError) as exc:
                self.get_logger().error(
                    f'recording to {recorder.path} failed: {exc}; recording stopped'
                )
                if self.recorder is recorder:
                    self.recorder = None

    def _checkpoint_recording(self) -> None:
        recorder = self.recorder
        if recorder is not None:
            try:
                recorder.checkpoint()
            except (OSError, RuntimeError) as exc:
                self.get_logger().error(
                    f'recording to {recorder.path} failed: {exc}; recording stopped'
                )
                self.recorder = None

    def _wait(self, predicate, timeout: float, what: str):
        """
        Poll ``predicate`` until it is truthy; raise TrialAborted on timeout or shutdown.

        A node name taken twice also stops the wait (checked every second): a twin that joins
        during a run, or one discovered only after the run was accepted, on a loaded machine.
        """
        now = time.monotonic()
        deadline, next_check = now + timeout, now + 1.0
        while (now := time.monotonic()) < deadline:
            if not rclpy.ok(context=self.context):
                raise TrialAborted('shutting down')
            value = predicate()
            if value:
                return value
            if now >= next_check:
                next_check = now + 1.0
                duplicates = self._duplicate_peers()
                if duplicates:
                    raise TrialAborted(duplicates)
            time.sleep(0.005)
        raise TrialAborted(f'timed out after {timeout:g} s waiting for {what}')

    def _await_latched(self, grace: float) -> None:
        """
        Give the latched topics (URDF, static frames) up to ``grace`` s to arrive before recording.

        A publisher this node has not yet discovered (a loaded machine, a run asked for right after
        the node started) has delivered nothing. Topics with a publisher are waited for up to
        ``grace``; topics with none only for the first second of the run, or until this node has
        been up ``grace`` s. One that arrives later in the run is still recorded when it comes.
        """

        def missing() -> list[str]:
            return [
                topic
                for topic, sub in self._latched_subs.items()
                if topic not in self._latched
                and (sub.get_publisher_count() > 0 or time.monotonic() < discovery_deadline)
            ]

        now = time.monotonic()
        deadline = now + grace
        discovery_deadline = min(deadline, max(now + 1.0, self.started_at + grace))
        while missing() and time.monotonic() < deadline and rclpy.ok(context=self.context):
            time.sleep(0.01)
        left = [
            f'{topic} ({self._latched_subs[topic].get_publisher_count()} publishers seen)'
            for topic in self._latched_subs
            if topic not in self._latched
        ]
        if left:
            self.get_logger().warning(
                f'recording starts without {", ".join(left)}: nothing received in {grace:g} s '
                '(is a state publisher running?); it is recorded if it comes during the run'
            )

    def _call(self, client, what: str, timeout: float = 10.0) -> Trigger.Response:
        if not client.wait_for_service(timeout_sec=timeout):
            raise TrialAborted(f'service {client.srv_name} is not available ({what})')
        future = client.call_async(Trigger.Request())
        self._wait(future.done, timeout, f'{client.srv_name} to answer')
        return future.result()

    def _duplicate_peers(self) -> str:
        """
        Why a run must be refused because a node name is taken twice ('' if it need not be).

        Checked: this node's name and the node the trials go through.
        """
        peer = self.sim_name if self.mode == 'sim' else self.bridge_name
        for name in (self.get_fully_qualified_name(), peer):
            count = nodes_named(self, name)
            if count > 1:
                return (
                    f'{count} nodes named {name} are in the graph: trials would be ambiguous; stop'
                    ' the extra one (or rename it with --ros-args -r __node:=NAME) and call adapt'
                    ' again'
                )
        return ''

    def _trial_engine(self) -> str | None:
        """
        Return what the trials run on.

        sim_node's ``engine`` parameter in sim mode (None if it does not answer), the real robot
        otherwise.
        """
        if self.mode != 'sim':
            return 'the real robot'
        if not self.sim_params_client.wait_for_service(timeout_sec=2.0):
            return None
        future = self.sim_params_client.call_async(GetParameters.Request(names=['engine']))
        try:
            self._wait(future.done, 5.0, "sim_node's parameters")
        except TrialAborted:
            return None
        values = future.result().values
        if values and values[0].type == ParameterType.PARAMETER_STRING:
            return values[0].string_value
        return None

    # -- trials -----------------------------------------------------------------------------
    def _gait_msg(self, niche: int) -> GaitParametersMsg:
        gait = from_genotype(self.archive.genotypes[niche]).replace(archive_index=int(niche))
        msg = gait_to_msg(gait)
        # the node's clock (sim time in a simulated graph), made unique: sim_node echoes the stamp
        # of the gait it plays, and that echo is how a trial knows its gait is on
        stamp = max(self.get_clock().now().nanoseconds, self._last_gait_stamp + 1)
        self._last_gait_stamp = stamp
        msg.header.stamp.sec, msg.header.stamp.nanosec = (
            stamp // 1_000_000_000,
            stamp % 1_000_000_000,
        )
        return msg

    def _publish_gait(self, niche: int) -> GaitParametersMsg:
        msg = self._gait_msg(niche)
        self.gait_pub.publish(msg)
        self._record('gait/parameters', msg)
        return msg

    def _upload(self, msg: GaitParametersMsg, timeout: float) -> UploadGait.Response:
        """
        Upload through bridge_node's ~/upload_gait service.

        Only its typed answer confirms an upload (a status text, or any other publisher, cannot).
        """
        if not self.upload_client.wait_for_service(timeout_sec=min(timeout, 10.0)):
            raise TrialAborted(
                f'service {self.upload_client.srv_name} is not available (is bridge_node running?)'
            )
        future = self.upload_client.call_async(UploadGait.Request(gait=msg, timeout=timeout))
        self._wait(future.done, timeout + 5.0, 'bridge_node to upload the gait')
        return future.result()

    def _sim_trial(self, niche: int, duration: float, timeout: float) -> float:
        for attempt in range(3):
            msg = self._publish_gait(niche)
            stamp, crab = _ns(msg.header.stamp), msg.crab_angle
            self._wait(
                lambda: self.active_stamp == stamp,
                timeout,
                'sim_node to play the gait (are gait_node and sim_node running?)',
            )
            before = self.reset_stamp or -1
            answer = self._call(self.reset_client, 'reset the simulation')
            if not answer.success:
                raise TrialAborted(f'sim_node refused the reset: {answer.message}')
            t0 = self._wait(
                lambda: self.reset_stamp if (self.reset_stamp or -1) > before else None,
                timeout,
                'the reset to take effect',
            )
            end = t0 + int(round(duration * 1e9))
            self._wait(
                lambda: self.odom and self.odom[-1].stamp_ns >= end,
                timeout,
                f'{duration:g} s of simulated odometry',
            )
            with self.data_lock:
                samples = list(self.odom)
            start = [s for s in samples if s.stamp_ns == t0]
            finish = [s for s in samples if abs(s.stamp_ns - end) < 1000]
            if start and finish:
                dx, dy = finish[-1].x - start[-1].x, finish[-1].y - start[-1].y
                return (dx * math.cos(crab) + dy * math.sin(crab)) / duration
            self.get_logger().warning(
                f'odometry sample lost in transport; repeating the trial (attempt {attempt + 2})'
            )
        raise TrialAborted(
            "odometry samples kept getting lost (is sim_node's publish_period_steps a divisor "
            'of the trial length in steps?)'
        )

    def _robot_trial(self, niche: int, duration: float, timeout: float) -> float:
        msg = self._gait_msg(niche)
        self._record('gait/parameters', msg)
        crab = msg.crab_angle
        answer = self._upload(msg, timeout)
        if not answer.success or answer.archive_index != niche:
            raise TrialAborted(answer.message or 'the robot did not confirm the upload')
        if self.mode == 'manual':
            self.reported.clear()
            self.get_logger().warning(
                f'trial with archive gait {niche}: start the robot, then report the distance '
                'walked with ~/report_distance'
            )
            distance = self._wait(
                lambda: self.reported[-1] if self.reported else None,
                max(timeout, 600.0),
                "the operator's distance (~/report_distance)",
            )
            return float(distance) / duration
        time.sleep(max(0.0, float(self.get_parameter('stand_still').value)))
        with self.data_lock:
            seen = len(self.odom)
        answer = self._call(self.start_client, 'start the trial')
        if not answer.success:
            raise TrialAborted(f'bridge_node did not start the trial: {answer.message}')
        started = time.monotonic()
        sample = self._wait(
            lambda: next((s for s in list(self.odom)[seen:] if s.received > started), None),
            duration + timeout,
            "the trial's odometry from bridge_node",
        )
        return sample.vx * math.cos(crab) + sample.vy * math.sin(crab)

    # -- the service --------------------------------------------------------------------------
    def _request_config(self, request: Adapt.Request) -> tuple[MboaConfig, float]:
        # a zero field means "the node's parameter"
        return run_settings(
            {
                name: getattr(request, name) or self.get_parameter(name).value
                for name in RUN_SETTINGS
            }
        )

    def _on_adapt(self, request: Adapt.Request, response: Adapt.Response):
        response.best_archive_index = -1
        if self.archive is None:
            response.success, response.message = False, self.archive_problem
            return response
        try:
            config, duration = self._request_config(request)
        except ValueError as exc:
            response.success, response.message = False, f'bad request: {exc}'
            return response
        duplicates = self._duplicate_peers()
        if duplicates:
            response.success, response.message = False, duplicates
            return response
        if not self.busy.acquire(blocking=False):
            response.success, response.message = False, 'an adaptation is already running'
            return response
        try:
            return self._run(config, duration, response)
        except Exception as exc:  # noqa: BLE001 - the service must answer and the node stay up
            self.get_logger().error(
                f'adaptation failed unexpectedly: {type(exc).__name__}: {exc}\n'
                f'{traceback.format_exc()}'
            )
            response.success = False
            response.message = f'internal error, run stopped: {type(exc).__name__}: {exc}'
            return response
        finally:
            self.cancel_requested = False
            self.busy.release()

    def _run(
        self, config: MboaConfig, duration: float, response: Adapt.Response
    ) -> Adapt.Response:
        archive = self.archive
        record_dir = self.get_parameter('record_dir').value
        timeout = float(self.get_parameter('trial_timeout').value)
        if self.get_parameter('use_sim_time').value:
            # one time base: nothing is stamped or recorded before the first /clock arrives
            try:
                self._wait(
                    lambda: self.get_clock().now().nanoseconds > 0,
                    timeout,
                    '/clock (is sim_node running?)',
                )
            except TrialAborted as exc:
                response.success, response.message = False, f'run not started: {exc}'
                return response
        if record_dir:
            self._await_latched(LATCHED_GRACE_S)
            try:
                recorder = create_recording(Path(record_dir).expanduser())
                response.mcap_path = str(recorder.path.resolve())
                with self._latched_lock:  # the URDF and the static frames come first
                    for topic, msg in self._latched.items():
                        self._write(recorder, topic, msg)
                    self.recorder = recorder
            except OSError as exc:
                self.get_logger().error(
                    f'cannot record in {record_dir}: {exc}; running without a recording'
                )
        trial_fn = self._sim_trial if self.mode == 'sim' else self._robot_trial
        note = engine_note(archive, self._trial_engine())
        self.get_logger().info(
            f'adaptation started: {archive.n_filled} gaits, at most {config.max_trials} trials '
            f'of {duration:g} s, alpha {config.alpha:g}, kappa {config.kappa:g}'
            + (f'; {note}' if note else '')
        )

        niches = archive.elite_indices()  # M-BOA's candidate index -> niche

        def on_trial(trial, niche, opt) -> None:
            best = opt.best()
            best_niche = niches[best.index]
            msg = AdaptationTrial()
            msg.header.stamp = self.get_clock().now().to_msg()
            msg.trial, msg.archive_index = trial.number, int(niche)
            msg.map_speed, msg.predicted_speed, msg.predicted_speed_std = (
                trial.predicted,
                trial.gp_mean,
                trial.gp_std,
            )
            msg.measured_speed, msg.best_speed, msg.best_archive_index = (
                trial.measured,
                best.measured,
                int(best_niche),
            )
            msg.descriptor = [float(x) for x in archive.descriptors[niche]]
            msg.gait = gait_to_msg(
                from_genotype(archive.genotypes[niche]).replace(archive_index=int(niche))
            )
            self.trial_pub.publish(msg)
            self._record('adapt/trials', msg)
            self._checkpoint_recording()  # a completed trial survives a kill or power loss
            self.get_logger().info(
                f'trial {trial.number}: gait {niche} walked {trial.measured:.3f} m/s '
                f'(map {trial.predicted:.3f}, GP {trial.gp_mean:.3f} +/- {trial.gp_std:.3f})'
            )

        try:
            result = adapt(
                archive,
                lambda niche: trial_fn(niche, duration, timeout),
                config,
                on_trial,
                should_cancel=lambda: self.cancel_requested,
            )
        finally:
            recorder, self.recorder = self.recorder, None
            if recorder is not None:
                recorder.close()
        response.success = result.success
        response.message = result.message + (f' ({note})' if note else '')
        response.trials = len(result.trials)
        response.elapsed = result.elapsed
        if result.best_niche >= 0:
            response.best_archive_index = result.best_niche
            response.best_speed = result.best_speed
            response.best_gait = gait_to_msg(
                from_genotype(archive.genotypes[result.best_niche]).replace(
                    archive_index=result.best_niche
                )
            )
            self._leave_on_best_gait(response.best_gait, timeout)
        self.get_logger().info(
            f'adaptation finished: {result.message}; {len(result.trials)} trials, best gait '
            f'{result.best_niche} at {result.best_speed:.3f} m/s'
        )
        return response

    def _leave_on_best_gait(self, msg: GaitParametersMsg, timeout: float) -> None:
        """Leave the robot (or the simulator) walking the best gait found."""
        if self.mode == 'sim':
            self.gait_pub.publish(msg)
            return
        try:
            answer = self._upload(msg, timeout)
        except TrialAborted as exc:
            self.get_logger().error(f'could not upload the best gait: {exc}')
            return
        if not answer.success:
            self.get_logger().error(f'could not upload the best gait: {answer.message}')


def main(args: list[str] | None = None) -> int:
    """Entry point of ``ros2 run hexapod_adapt adapt_node``."""
    return run_node(AdaptNode, args, num_threads=4, parameters=PARAMETERS)


if __name__ == '__main__':
    sys.exit(main())
