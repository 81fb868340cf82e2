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
``ros2 run hexapod_adapt navigate_node``: walk to a place after damage, learning on the way.

Serves the ``navigate`` action (hexapod_msgs/Navigate), modelled on nav2's NavigateToPose: a goal
(x, y) in ``odom`` is pursued step by step over the navigation repertoire (``repertoire``
parameter, by default the shipped one) with the learned correction of
:mod:`hexapod_navigation.planner`, with no resets. Through gait_node + sim_node (``mode:=sim``) or
bridge_node (``mode:=robot``). The pose comes from ``odom``, or from ``pose_topic`` (a
geometry_msgs/PoseStamped or nav_msgs/Odometry, e.g. motion capture).

* An invalid goal (not finite, beyond ``max_range``, outside the arena, no repertoire, no pose
  yet) is rejected; the reason is logged and published on ``navigate/status``.
* A new goal preempts the one being pursued (that one ends PREEMPTED); a cancel stops the robot
  within one gait cycle; a client that vanishes leaves the goal to run to its end.
* What was learned about the damage is kept from goal to goal; ``~/forget`` drops it (after a
  repair, or new damage).

Publishes ``navigate/goal`` (visualization_msgs/Marker, latched) and ``navigate/status``. With
``record_dir`` set, each goal is recorded to an MCAP file there (odometry, frames, joint states,
gaits, the goal marker, the URDF): its path replays in Foxglove.
"""

from __future__ import annotations

from dataclasses import asdict, fields
import math
import sys
import threading
import time

from builtin_interfaces.msg import Duration
from diagnostic_msgs.msg import DiagnosticStatus
from geometry_msgs.msg import PoseStamped
from hexapod_adapt.mapping.archive import ArchiveError, load_archive
from hexapod_adapt.online.adaptation import TrialAborted
from hexapod_adapt.online.trials import OdomLog, Waiter
from hexapod_adapt.ros.graph_port import GraphPort, RECORDED_TYPES, RecordedTopics, stamp_ns
from hexapod_adapt.ros.recording import type_name
from hexapod_adapt.ros.run_recording import RunRecording
from hexapod_gait.ros_conversions import gait_to_msg
from hexapod_gait.ros_glue import declare, LATCHED, ODOM, ParamSpec, publish_status, run_node
from hexapod_msgs.action import Navigate
from hexapod_navigation.bodies import PoseLog, PoseSample, RobotGraphBody, SimGraphBody
from hexapod_navigation.episode import Feedback, Outcome, run_episode
from hexapod_navigation.navigate_msgs import OUTCOME_CODES, pose_msg
from hexapod_navigation.planner import goal_problem, NavigationConfig, Pose2D, RepertoirePolicy
from hexapod_navigation.repertoire import Repertoire, shipped_repertoire
from hexapod_navigation.step_bank import load_step_bank, shipped_step_bank
from hexapod_sim.simulator import quat_to_euler
from nav_msgs.msg import Odometry
import rclpy
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from rclpy.node import Node
from std_srvs.srv import Trigger
from visualization_msgs.msg import Marker

MODES = ('sim', 'robot')
#: What a goal's recording holds: the sensors and frames an adaptation run records, and the goal.
RECORDED = {
    **{topic: name for topic, name in RECORDED_TYPES.items() if topic != 'adapt/trials'},
    'navigate/goal': type_name(Marker),
}
LATCHED_GRACE_S = 5.0  # how long a recording waits at its start for the URDF and static frames
FIRST_POSE_WAIT_S = 5.0  # how long a goal waits for the pose source's first message
_DEFAULTS = NavigationConfig()
#: NavigationConfig's fields that are node parameters (the GP's settings and the limits).
CONFIG_PARAMS = tuple(f.name for f in fields(NavigationConfig) if f.name not in ('arena', 'learn'))

PARAMETERS = (
    ParamSpec('mode', 'sim', 'sim (gait_node + sim_node) or robot (bridge_node)', read_only=True),
    ParamSpec(
        'repertoire',
        '',
        'navigation repertoire file (.npz); empty = the shipped one',
        read_only=True,
    ),
    ParamSpec(
        'bank_file',
        '',
        "the repertoire's damage bank (hexapod_navigation.step_bank), weighed when use_bank is"
        ' true; empty = the shipped one (it fits the shipped repertoire only)',
        read_only=True,
    ),
    ParamSpec('pose_topic', '', 'external pose source; empty = odom', read_only=True),
    ParamSpec(
        'pose_type',
        'pose',
        "the pose topic's type: pose (PoseStamped) or odometry",
        read_only=True,
    ),
    ParamSpec('sim_node', 'sim_node', 'name of the simulator node', read_only=True),
    ParamSpec('bridge_node', 'bridge_node', 'name of the bridge node', read_only=True),
    ParamSpec(
        'trial_duration', 2.0, "robot mode: bridge_node's trial_duration [s]", read_only=True
    ),
    # the node reads every parameter once, at start-up: all are read-only, so that setting one
    # at run time is refused instead of silently doing nothing
    ParamSpec(
        'arena', 0.0, 'half-width of the square arena around odom [m]; 0 = none', read_only=True
    ),
    ParamSpec(
        'learn',
        True,
        'learn the damage while walking (false: the repertoire as measured)',
        read_only=True,
    ),
    ParamSpec(
        'timeout',
        10.0,
        'longest wait for the graph to answer [s]',
        read_only=True,
        range=(0.1, 600.0),
    ),
    ParamSpec(
        'record_dir',
        '',
        'record each goal to an MCAP file here; empty = no recording',
        read_only=True,
    ),
    *(
        # each of the type of its default (min_stance_legs is a whole number)
        ParamSpec(name, getattr(_DEFAULTS, name), f'NavigationConfig.{name}', read_only=True)
        for name in CONFIG_PARAMS
    ),
)


class NavigateNode(Node):
    """Serve the ``navigate`` action over the navigation repertoire."""

    def __init__(self) -> None:
        super().__init__('navigate_node')
        values = declare(self, PARAMETERS)
        self.mode = values['mode']
        self.problem = ''
        if self.mode not in MODES:
            raise ValueError(
                f'parameter mode must be one of {", ".join(MODES)}, got {self.mode!r}'
            )
        if values['pose_type'] not in ('pose', 'odometry'):
            raise ValueError(
                f'parameter pose_type must be pose or odometry, got {values["pose_type"]!r}'
            )
        self.config = self._config()  # ValueError names a bad setting
        self.repertoire: Repertoire | None = None
        path = values['repertoire'] or str(shipped_repertoire())
        self.hypotheses = None  # the damage bank's step tables, if one fits the repertoire
        try:
            archive = load_archive(path)
            self.repertoire = Repertoire.from_archive(archive)
        except ArchiveError as exc:
            self.problem = f'no navigation repertoire: {exc}'
        else:
            bank, why = load_step_bank(
                values['bank_file'] or shipped_step_bank(),
                self.repertoire,
                self.repertoire.engine,
            )
            if bank is not None:
                self.hypotheses = bank.steps
                self.get_logger().info(f'damage bank: {len(bank)} damage hypotheses')
            elif self.config.use_bank:
                self.get_logger().warning(f'no damage bank, the GP learns alone: {why}')
        self.policy = self._policy() if self.repertoire else None

        self.status_pub = self.create_publisher(DiagnosticStatus, 'navigate/status', LATCHED)
        self.marker_pub = self.create_publisher(Marker, 'navigate/goal', LATCHED)
        self.poses, self.trial_poses = PoseLog(), PoseLog()
        self.waiter = Waiter(lambda: rclpy.ok(context=self.context))
        self.recording = RunRecording(
            self.resolve_topic_name,
            lambda: self.get_clock().now().nanoseconds,
            self.get_logger().error,
        )
        self.port = GraphPort(
            self, values['sim_node'], values['bridge_node'], OdomLog(), self.recording
        )
        self.record_dir = values['record_dir']
        # the sensor subscriptions only when recording: at sim_node's faster-than-real-time rates
        # their callbacks delayed the odometry the steps are timed by
        self.recorded = RecordedTopics(self, self.recording) if self.record_dir else None
        self.port.wait = self.waiter.until
        self.stop_client = self.create_client(Trigger, f'{values["bridge_node"]}/stop_trial')
        self.trial_duration = values['trial_duration']
        sensors = MutuallyExclusiveCallbackGroup()
        external = bool(values['pose_topic'])
        if external:
            kind = PoseStamped if values['pose_type'] == 'pose' else Odometry
            self.create_subscription(
                kind, values['pose_topic'], self._on_pose, ODOM, callback_group=sensors
            )
        odom_log = self.trial_poses if (self.mode == 'robot' or external) else self.poses
        self.create_subscription(
            Odometry, 'odom', lambda m: self._log(odom_log, m), ODOM, callback_group=sensors
        )
        timeout = self.timeout = values['timeout']
        if self.mode == 'sim':
            self.body = SimGraphBody(self, self.poses, self.waiter, timeout)
        else:
            self.body = RobotGraphBody(
                self,
                self.poses,
                self.trial_poses,
                self.waiter,
                values['trial_duration'],
                external,
                timeout,
            )
        self._lock = threading.Lock()
        self._driving = threading.Lock()
        self._active = None
        self._preempted: set = set()
        work = ReentrantCallbackGroup()
        self.server = ActionServer(
            self,
            Navigate,
            'navigate',
            execute_callback=self._execute,
            goal_callback=self._on_goal,
            handle_accepted_callback=self._on_accepted,
            cancel_callback=lambda _: CancelResponse.ACCEPT,
            callback_group=work,
        )
        self.create_service(Trigger, '~/forget', self._on_forget, callback_group=work)
        if self.problem:
            self._status(DiagnosticStatus.ERROR, self.problem)
        else:
            self._status(
                DiagnosticStatus.OK,
                f'navigate_node ready: mode {self.mode}, {len(self.repertoire)} gaits in the'
                f' repertoire, pose from {values["pose_topic"] or "odom"}',
            )

    def _policy(self) -> RepertoirePolicy:
        return RepertoirePolicy(self.repertoire, self.config, self.hypotheses)

    # -- settings, inputs ---------------------------------------------------------------------
    def _config(self) -> NavigationConfig:
        values = {name: self.get_parameter(name).value for name in CONFIG_PARAMS}
        arena = self.get_parameter('arena').value
        return NavigationConfig(
            **values, arena=arena if arena > 0 else None, learn=self.get_parameter('learn').value
        )

    def _status(self, level: bytes, message: str) -> None:
        publish_status(self, self.status_pub, level, message, 'navigate_node')

    @staticmethod
    def _sample(msg, pose) -> PoseSample:
        p, q = pose.position, pose.orientation
        roll, pitch, yaw = quat_to_euler((q.x, q.y, q.z, q.w))
        return PoseSample(
            stamp_ns(msg.header.stamp), Pose2D(p.x, p.y, yaw), time.monotonic(), roll, pitch
        )

    def _log(self, log: PoseLog, msg: Odometry) -> None:
        log.append(self._sample(msg, msg.pose.pose))

    def _on_pose(self, msg) -> None:
        pose = msg.pose.pose if isinstance(msg, Odometry) else msg.pose
        self.poses.append(self._sample(msg, pose))

    # -- NavigationPort (the graph side of the bodies) -------------------------------------------
    def publish_gait(self, gait) -> int:
        """Publish a gait with a unique stamp; return the stamp [ns]."""
        msg = gait_to_msg(gait)
        stamp = self.port.stamp(msg)
        self.port.publish(msg)
        return stamp

    def active_stamp(self) -> int | None:
        """Return the stamp of the gait sim_node plays."""
        return self.port.active_stamp()

    def activated_at(self, stamp: int) -> int | None:
        """Return the simulation time [ns] the gait stamped ``stamp`` took effect."""
        return self.port.activated_at(stamp)

    def upload(self, gait, timeout: float) -> tuple[bool, str]:
        """Upload through bridge_node."""
        answer = self.port.upload_msg(gait_to_msg(gait), timeout)
        return answer.success, answer.message

    def start_trial(self) -> tuple[bool, str]:
        """Start a trial on the robot."""
        return self.port.start_trial()

    def stop_trial(self) -> tuple[bool, str]:
        """Stop the robot's trial."""
        answer = self.port.call(self.stop_client, 'stop the trial', timeout=2.0)
        return answer.success, answer.message

    # -- the action ----------------------------------------------------------------------------
    def _bridge_trial_problem(self) -> str:
        """Robot mode: why bridge_node's trials do not fit this node's steps ('' if they do)."""
        # as long as any answer from the graph (a loaded machine discovers a service late)
        bridge = self.port.bridge_trial(self.timeout, self.timeout)
        if bridge is None:
            return ''  # not up: the upload will say so, with its own reason
        duration, settle = bridge
        if abs(duration - self.trial_duration) > 1e-6:
            return (
                f'bridge_node walks {duration:g} s per trial but navigate_node steps are'
                f' {self.trial_duration:g} s: set both trial_duration parameters alike'
            )
        if settle > 0:
            return (
                f'bridge_node settles {settle:g} s before it times a trial, but navigate_node'
                " steps are walks from standing: set bridge_node's trial_settle to 0"
            )
        return ''

    def _goal_problem(self, goal) -> str:
        if self.policy is None:
            return self.problem
        if self.mode == 'robot':
            problem = self._bridge_trial_problem()
            if problem:
                return problem
        for name in ('tolerance', 'time_limit'):
            value = getattr(goal, name)
            if not math.isfinite(value) or value < 0:
                return f'{name} must be 0 (the default) or a positive number, got {value}'
        if self.mode == 'sim' or self.body.external:
            # a goal sent just after start-up waits a little for the first pose
            try:
                latest = self.waiter.until(self.poses.latest, FIRST_POSE_WAIT_S, 'a pose')
            except TrialAborted:
                return 'no pose received yet (is the pose source publishing?)'
            start = latest.pose
        else:
            start = self.body.pose()
        return goal_problem(goal.x, goal.y, start, self.config)

    def _on_goal(self, goal) -> GoalResponse:
        problem = self._goal_problem(goal)
        if problem:
            self._status(DiagnosticStatus.WARN, f'goal ({goal.x}, {goal.y}) rejected: {problem}')
            return GoalResponse.REJECT
        return GoalResponse.ACCEPT

    def _on_accepted(self, handle) -> None:
        with self._lock:
            if self._active is not None:
                self._preempted.add(self._active)
        handle.execute()

    @staticmethod
    def _key(handle) -> bytes:
        return bytes(handle.goal_id.uuid)

    def _execute(self, handle) -> Navigate.Result:
        goal = handle.request
        with self._driving:  # a preempted goal finishes first
            with self._lock:
                self._active = self._key(handle)
            config = NavigationConfig(
                **{
                    **asdict(self.config),
                    'tolerance': goal.tolerance or self.config.tolerance,
                    'time_limit': goal.time_limit or self.config.time_limit,
                }
            )
            self.policy.config = config
            path = self._start_recording()
            self._marker(goal.x, goal.y, config.tolerance)

            def stopped() -> bool:
                return (
                    handle.is_cancel_requested
                    or self._key(handle) in self._preempted
                    or not rclpy.ok(context=self.context)
                )

            def feedback(f: Feedback) -> None:
                self.recording.checkpoint()  # every step survives a kill or a power loss
                msg = Navigate.Feedback(distance_remaining=f.distance_left, steps=f.steps)
                msg.current_pose = pose_msg(f.pose, self.get_clock().now().to_msg())
                msg.prediction_error = f.prediction_error
                walked = int(f.walking_time * 1e9)
                msg.navigation_time = Duration(
                    sec=walked // 1_000_000_000, nanosec=walked % 1_000_000_000
                )
                handle.publish_feedback(msg)

            self._status(DiagnosticStatus.OK, f'navigating to ({goal.x:.2f}, {goal.y:.2f})')
            try:
                result = run_episode(
                    self.body, self.policy, (goal.x, goal.y), config, stopped, feedback
                )
            except TrialAborted as exc:  # the graph stopped answering while standing up
                result = None
                reason = str(exc)
            finally:
                self.recording.stop()
            with self._lock:
                preempted = self._key(handle) in self._preempted
                self._preempted.discard(self._key(handle))
                self._active = None
        out = Navigate.Result(recording=str(path) if path else '')
        if result is None:
            out.outcome, out.reason = Navigate.Result.FAILED, reason
            handle.abort()
            return out
        out.reached, out.reason = result.reached, result.reason
        out.outcome = OUTCOME_CODES[result.outcome]
        out.walking_time, out.path_length, out.steps = (
            result.walking_time,
            result.path_length,
            result.steps,
        )
        out.distance_left = result.end.distance_to(goal.x, goal.y)
        out.final_pose = pose_msg(result.end, self.get_clock().now().to_msg())
        if result.outcome is Outcome.CANCELED and preempted and not handle.is_cancel_requested:
            out.outcome, out.reason = Navigate.Result.PREEMPTED, 'preempted by a newer goal'
            handle.abort()
        elif result.outcome is Outcome.CANCELED:
            handle.canceled()
        elif result.reached:
            handle.succeed()
        else:
            handle.abort()
        self._status(
            DiagnosticStatus.OK if result.reached else DiagnosticStatus.WARN,
            f'goal ({goal.x:.2f}, {goal.y:.2f}): {out.reason} after {result.walking_time:.1f} s',
        )
        return out

    def _start_recording(self):
        """Open this goal's MCAP file (None if the node does not record, or cannot)."""
        if not self.record_dir:
            return None
        left = self.recorded.await_latched(LATCHED_GRACE_S)
        if left:
            self.get_logger().warning(f'recording starts without {", ".join(left)}')
        return self.recording.start(self.record_dir, RECORDED, prefix='navigate')

    def shutdown(self) -> None:
        """Ctrl-C / SIGTERM mid-goal: finish the MCAP file (called by run_node)."""
        self.recording.stop()

    def _marker(self, x: float, y: float, tolerance: float) -> None:
        m = Marker(ns='navigate', id=0, type=Marker.CYLINDER, action=Marker.ADD)
        m.header.frame_id = 'odom'
        m.header.stamp = self.get_clock().now().to_msg()
        m.pose.position.x, m.pose.position.y, m.pose.orientation.w = x, y, 1.0
        m.scale.x = m.scale.y = 2.0 * tolerance
        m.scale.z = 0.02
        m.color.r, m.color.g, m.color.a = 0.1, 0.8, 0.6
        self.marker_pub.publish(m)
        self.recording.record('navigate/goal', m)

    def _on_forget(self, request, response):
        if self._driving.locked():
            response.success, response.message = False, 'a goal is being pursued; cancel it first'
        elif self.repertoire is None:
            response.success, response.message = False, self.problem
        else:
            self.policy = self._policy()
            response.success, response.message = (
                True,
                'what was learned about the damage is dropped',
            )
        return response


def main(args: list[str] | None = None) -> int:
    """Entry point of ``ros2 run hexapod_adapt navigate_node``."""
    return run_node(NavigateNode, args, num_threads=4, parameters=PARAMETERS)


if __name__ == '__main__':
    sys.exit(main())
