# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``ros2 run hexapod_navigation navigate_node``: walk to a place after damage, learning on the way.

Serves the ``navigate`` action (hexapod_msgs/Navigate), modelled on nav2's NavigateToPose: a goal
(x, y) in ``odom`` is pursued step by step over the navigation repertoire (``repertoire``
parameter, by default the shipped one) with the learned correction of
:mod:`hexapod_navigation.planner`, with no resets. Through gait_node + sim_node (``mode:=sim``) or
bridge_node (``mode:=robot``). The pose comes from ``odom``, or from ``pose_topic`` (a
geometry_msgs/PoseStamped or nav_msgs/Odometry, e.g. motion capture).

* An invalid goal (not finite, beyond ``max_range``, outside the arena, no repertoire) is
  rejected; the reason is logged and published on ``navigate/status``. What needs an answer from
  the graph (the first pose, bridge_node's trial length) is checked when the goal's turn comes,
  and a goal that fails it is aborted with the reason.
* A new goal preempts the one being pursued (that one ends PREEMPTED); goals superseded before
  their turn end PREEMPTED without walking, so a storm of goals is answered at once and only the
  newest is walked (:mod:`hexapod_navigation.goal_turns`); a cancel stops the robot within one
  gait cycle; a client that vanishes leaves the goal to run to its end.
* What was learned about the damage is kept from goal to goal; ``~/forget`` drops it (after a
  repair, or new damage).
* Robot mode: dead servos reported on ``servo_failures`` by the configured ``bridge_node`` (and
  no other node: the graph names a topic's publishers) become that damage, favoured among the
  damage bank's hypotheses from the next goal (``prior_reported``); ``~/forget`` drops them.
* ``~/set_known_damage`` (hexapod_msgs/SetLegFailure): the operator names the damage, of any
  kind, for what no servo report can tell (a locked joint, a broken tibia). It wins over the
  servo reports from the next goal, as they do; an empty request or ``~/forget`` drops it.

Publishes ``navigate/goal`` (visualization_msgs/Marker, latched) and ``navigate/status``. With
``record_dir`` set, each goal is recorded to an MCAP file there (odometry, frames, joint states,
gaits, the goal marker, the URDF): its path replays in Foxglove.
"""

from __future__ import annotations

import math
import sys

from diagnostic_msgs.msg import DiagnosticStatus
from geometry_msgs.msg import PoseStamped
from hexapod_adapt.online.adaptation import TrialAborted
from hexapod_adapt.online.prior import damage_of_request, KnownDamage
from hexapod_adapt.online.trials import OdomLog, Waiter
from hexapod_adapt.ros.graph_port import (
    GraphPort,
    RECORDED_TYPES,
    RecordedTopics,
    servo_report_problem,
)
from hexapod_adapt.ros.run_recording import RunRecording
from hexapod_msgs.action import Navigate
from hexapod_msgs.msg import ServoFailure
from hexapod_msgs.srv import SetLegFailure
from hexapod_navigation import navigate_msgs as conv
from hexapod_navigation import node_settings as settings
from hexapod_navigation.bodies import PoseLog, RobotGraphBody, SimGraphBody
from hexapod_navigation.config import goal_problem
from hexapod_navigation.episode import BodyFailure, Feedback, Outcome, run_episode
from hexapod_navigation.goal_turns import GoalTurns
from hexapod_navigation.loading import load_navigation
from hexapod_navigation.planner import RepertoirePolicy
from hexapod_navigation.repertoire import shipped_repertoire
from hexapod_navigation.specialists import shipped_specialists
from hexapod_navigation.step_bank import reported_note, shipped_step_bank
from hexapod_sim.damage import Damage
from hexapod_util.recording import type_name
from hexapod_util.ros_glue import (
    ACTION_SERVICES,
    declare,
    EVENTS,
    LATCHED,
    param_specs,
    POSES,
    publish_status,
    run_node,
)
from nav_msgs.msg import Odometry
import rclpy
from rclpy._rclpy_pybind11 import InvalidHandle, RCLError
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from rclpy.node import Node
from std_srvs.srv import Trigger
from visualization_msgs.msg import Marker

#: What a goal's recording holds: the sensors and frames an adaptation run records, and the goal.
RECORDED = {
    **{topic: name for topic, name in RECORDED_TYPES.items() if topic != 'adapt/trials'},
    'navigate/goal': type_name(Marker),
}
FIRST_POSE_WAIT_S = 5.0  # how long a goal waits for the pose source's first message
#: A goal walks once it has been the newest this long [s]: of a burst of goals only the last walks.
GOAL_SETTLE_S = 0.5
PARAMETERS = param_specs(settings.SETTINGS)


class NavigateNode(Node):
    """Serve the ``navigate`` action over the navigation repertoire."""

    def __init__(self) -> None:
        super().__init__('navigate_node')
        values = declare(self, PARAMETERS)
        problem = settings.node_problem(values)
        if problem:
            raise ValueError(problem)
        self.mode = values['mode']
        self.config = settings.navigation_config(values)  # ValueError names a bad setting
        use_specialists = self.config.use_bank and self.config.specialists
        data = load_navigation(
            values['repertoire'] or shipped_repertoire(),
            values['bank_file'] or shipped_step_bank(),
            (values['specialists_file'] or shipped_specialists()) if use_specialists else None,
            self.config.specialist_max_tilt,
        )
        self.repertoire, self.problem = data.repertoire, data.problem
        self.bank = data.bank  # the damage hypotheses
        if data.bank is not None:
            self.get_logger().info(f'damage bank: {len(data.bank)} damage hypotheses')
        elif self.repertoire is not None and self.config.use_bank:
            self.get_logger().warning(f'no damage bank, the GP learns alone: {data.no_bank}')
        if data.specialists:
            self.get_logger().info(f'{data.specialists} steps of gaits made for a damage')
        elif self.repertoire is not None and use_specialists:
            self.get_logger().warning(f'no gaits made for a damage: {data.no_specialists}')
        self.known = KnownDamage()  # robot mode: the bridge's servo reports
        self.named: Damage | None = None  # the operator's word (~/set_known_damage)
        self.reports_changed = False  # a report came since the policy was made
        self.bridge_name = values['bridge_node']
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
        stop_client = self.create_client(Trigger, f'{values["bridge_node"]}/stop_trial')
        graph = conv.GraphNavigationPort(self.port, stop_client)
        self.trial_duration = values['trial_duration']
        # poses: the newest few only (POSES), so a reader that falls behind the source skips
        # stale poses instead of timing steps by them
        sensors = MutuallyExclusiveCallbackGroup()
        external = bool(values['pose_topic'])
        if external:
            kind = PoseStamped if values['pose_type'] == 'pose' else Odometry
            self.create_subscription(
                kind,
                values['pose_topic'],
                lambda m: self.poses.append(conv.pose_sample(m)),
                POSES,
                callback_group=sensors,
            )
        odom_log = self.trial_poses if (self.mode == 'robot' or external) else self.poses
        self.create_subscription(
            Odometry,
            'odom',
            lambda m: odom_log.append(conv.pose_sample(m)),
            POSES,
            callback_group=sensors,
        )
        if self.mode == 'robot':
            self.create_subscription(  # its own group: a report may wait on the graph
                ServoFailure,
                'servo_failures',
                self._on_servo_failure,
                EVENTS,
                callback_group=MutuallyExclusiveCallbackGroup(),
            )
        timeout = self.timeout = values['timeout']
        if self.mode == 'sim':
            self.body = SimGraphBody(
                graph, self.poses, self.waiter, timeout, self.config.tip_guard
            )
        else:
            self.body = RobotGraphBody(
                graph,
                self.poses,
                self.trial_poses,
                self.waiter,
                values['trial_duration'],
                external,
                timeout,
            )
        self.turns = GoalTurns(GOAL_SETTLE_S)
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
            goal_service_qos_profile=ACTION_SERVICES,
            result_service_qos_profile=ACTION_SERVICES,
            cancel_service_qos_profile=ACTION_SERVICES,
        )
        self.create_service(Trigger, '~/forget', self._on_forget, callback_group=work)
        self.create_service(
            SetLegFailure, '~/set_known_damage', self._on_set_known_damage, callback_group=work
        )
        if self.problem:
            self._status(DiagnosticStatus.ERROR, self.problem)
        else:
            self._status(
                DiagnosticStatus.OK,
                f'navigate_node ready: mode {self.mode}, {len(self.repertoire)} gaits in the'
                f' repertoire, pose from {values["pose_topic"] or "odom"}',
            )

    def _known_damage(self) -> Damage | None:
        """Return the damage the next goal starts from: the operator's, else the servo reports'."""
        return self.named if self.named is not None else self.known.servo_damage()

    def _policy(self) -> RepertoirePolicy:
        self.reports_changed = False
        reported = self._known_damage()
        return RepertoirePolicy.with_bank(self.repertoire, self.config, self.bank, reported)

    def _on_servo_failure(self, msg: ServoFailure) -> None:
        problem = servo_report_problem(self, self.bridge_name)
        if problem:
            self.get_logger().error(
                f'servo {msg.servo_id} (leg {msg.leg}) reported dead: {problem}'
            )
            return
        said = self.known.from_servo(int(msg.servo_id), int(msg.leg), str(msg.joint))
        self.reports_changed = True  # the next goal starts from them
        if self.named is not None:
            note = f'the damage the operator named, {self.named.label}, still wins'
        else:
            note = reported_note(self.bank, self.known.servo_damage(), self.config.prior_reported)
        self.get_logger().warning(f'{said}; {note}')

    def _on_set_known_damage(self, request, response):
        try:
            named = damage_of_request(request)
        except ValueError as exc:
            response.success, response.message = False, f'bad request: {exc}'
            return response
        self.named = named
        self.reports_changed = True  # the next goal starts from it
        damage = self._known_damage()
        response.success = True
        response.failed_legs = list(damage.failed_legs) if damage else []
        response.damage = damage.label if damage else ''
        if named is None:
            response.message = 'the damage the operator named is dropped; ' + reported_note(
                self.bank, damage, self.config.prior_reported
            )
        else:
            note = reported_note(self.bank, named, self.config.prior_reported)
            response.message = f'{named.label}, as the operator says: {note}'
        self.get_logger().warning(response.message)
        return response

    def _status(self, level: bytes, message: str) -> None:
        self._unless_closing(
            publish_status, self, self.status_pub, level, message, 'navigate_node'
        )

    # -- the action ----------------------------------------------------------------------------
    def _goal_problem(self, goal) -> str:
        """Say what is wrong with ``goal`` that can be told at once ('' if nothing yet)."""
        if self.policy is None:
            return self.problem
        problem = settings.goal_settings_problem(goal.tolerance, goal.time_limit)
        if problem:
            return problem
        # before the first pose, all but the range (CI once saw a NaN goal accepted then)
        return goal_problem(goal.x, goal.y, self._known_pose(), self.config)

    def _known_pose(self):
        """Return the robot's pose if known now (None before the pose source's first message)."""
        if self.mode == 'sim' or self.body.external:
            latest = self.poses.latest()
            return latest.pose if latest is not None else None
        return self.body.pose()  # dead reckoning: always known

    def _start_problem(self, goal) -> str:
        """
        Say what stops the goal whose turn came, asking the graph ('' if nothing).

        Kept out of the goal callback: an executor thread that waits there is one the answers
        it waits for cannot use, and a burst of goals then starved the node.
        """
        if self.mode == 'robot':
            # as long as any answer from the graph (a loaded machine discovers a service late)
            bridge = self.port.bridge_trial(self.timeout, self.timeout)
            problem = settings.bridge_trial_problem(bridge, self.trial_duration)
            if problem:
                return problem
        if self._known_pose() is None:  # a goal sent just after start-up waits for a pose
            try:
                self.waiter.until(self.poses.latest, FIRST_POSE_WAIT_S, 'a pose')
            except TrialAborted:
                return 'no pose received yet (is the pose source publishing?)'
        return goal_problem(goal.x, goal.y, self._known_pose(), self.config)

    def _on_goal(self, goal) -> GoalResponse:
        problem = self._goal_problem(goal)  # never waits: every request is answered at once
        if problem:
            self._status(DiagnosticStatus.WARN, f'goal ({goal.x}, {goal.y}) rejected: {problem}')
            return GoalResponse.REJECT
        return GoalResponse.ACCEPT

    def _on_accepted(self, handle) -> None:
        self.turns.accepted(self._key(handle))  # the goal being walked stops at its next check
        self._unless_closing(handle.execute)

    @staticmethod
    def _key(handle) -> bytes:
        return bytes(handle.goal_id.uuid)

    def _execute(self, handle) -> Navigate.Result:
        key, goal = self._key(handle), handle.request
        # a goal superseded before its turn ends at once, without walking, and waiting holds no
        # lock the node's other callbacks need (a storm of goals is answered at once)
        if not self.turns.wait_turn(key, lambda: handle.is_cancel_requested):
            return self._end_unwalked(handle)
        problem = self._start_problem(goal)
        if problem and not rclpy.ok(context=self.context):
            self.turns.done(key)
            return self._end_unwalked(handle)  # the wait for a pose ended with the node
        if problem:
            self.turns.done(key)
            self._status(DiagnosticStatus.WARN, f'goal ({goal.x}, {goal.y}) aborted: {problem}')
            self._unless_closing(handle.abort)
            return Navigate.Result(outcome=Navigate.Result.FAILED, reason=problem)
        try:
            if self.reports_changed:  # what was learned before a new dead servo is stale
                self.policy = self._policy()
            config = settings.goal_config(self.config, goal.tolerance, goal.time_limit)
            self.policy.config = config
            path = self._start_recording()
            marker = conv.goal_marker(goal.x, goal.y, config.tolerance, self._now())
            self.marker_pub.publish(marker)
            self.recording.record('navigate/goal', marker)

            def stopped() -> bool:
                return (
                    handle.is_cancel_requested
                    or self.turns.superseded(key)
                    or not rclpy.ok(context=self.context)
                )

            def feedback(f: Feedback) -> None:
                self.recording.checkpoint()  # every step survives a kill or a power loss
                if f.tilted:
                    self.get_logger().warning(
                        f'step {f.steps} tilted the robot past the tip guard'
                        f' ({math.degrees(config.tip_guard):.0f} deg): stopped it, the robot'
                        ' stood, and that step is not taken again'
                    )
                self._unless_closing(handle.publish_feedback, conv.feedback_msg(f, self._now()))

            self._status(DiagnosticStatus.OK, f'navigating to ({goal.x:.2f}, {goal.y:.2f})')
            try:
                result = run_episode(
                    self.body, self.policy, (goal.x, goal.y), config, stopped, feedback
                )
            except (TrialAborted, BodyFailure) as exc:  # the graph stopped answering
                result, reason = None, str(exc)
            finally:
                self.recording.stop()
            preempted = self.turns.superseded(key)
        finally:
            self.turns.done(key)
        if not rclpy.ok(context=self.context):
            self._unless_closing(handle.abort)
            return Navigate.Result(outcome=Navigate.Result.FAILED, reason='shutting down')
        recording = str(path) if path else ''
        if result is None:
            self._unless_closing(handle.abort)
            return Navigate.Result(
                outcome=Navigate.Result.FAILED, reason=reason, recording=recording
            )
        out = conv.result_msg(result, (goal.x, goal.y), recording, self._now())
        if result.outcome is Outcome.CANCELED and preempted and not handle.is_cancel_requested:
            out.outcome, out.reason = Navigate.Result.PREEMPTED, 'preempted by a newer goal'
            self._unless_closing(handle.abort)
        elif result.outcome is Outcome.CANCELED:
            self._unless_closing(handle.canceled)
        elif result.reached:
            self._unless_closing(handle.succeed)
        else:
            self._unless_closing(handle.abort)
        self._status(
            DiagnosticStatus.OK if result.reached else DiagnosticStatus.WARN,
            f'goal ({goal.x:.2f}, {goal.y:.2f}): {out.reason} after {result.walking_time:.1f} s',
        )
        return out

    def _unless_closing(self, call, *args) -> None:
        """
        Call ``call(*args)`` (a goal handle's ``abort`` ..., a status message), which publishes.

        At shutdown the publishing fails (the handle's state is still set): that is ignored.
        """
        try:
            call(*args)
        except (RCLError, InvalidHandle):  # a closing node has no one to tell
            if rclpy.ok(context=self.context):
                raise

    def _end_unwalked(self, handle) -> Navigate.Result:
        """End a goal that never got its turn: cancelled, superseded, or the node closing."""
        if not rclpy.ok(context=self.context):
            self._unless_closing(handle.abort)
            return Navigate.Result(outcome=Navigate.Result.FAILED, reason='shutting down')
        if handle.is_cancel_requested:
            self._unless_closing(handle.canceled)
            return Navigate.Result(outcome=Navigate.Result.CANCELED, reason='canceled')
        self._unless_closing(handle.abort)
        return Navigate.Result(
            outcome=Navigate.Result.PREEMPTED, reason='preempted by a newer goal before it started'
        )

    def _now(self):
        return self.get_clock().now().to_msg()

    def _start_recording(self):
        """Open this goal's MCAP file (None if the node does not record, or cannot)."""
        if not self.record_dir:
            return None
        warn = self.get_logger().warning
        return self.recorded.start(self.record_dir, RECORDED, warn, prefix='navigate')

    def shutdown(self) -> None:
        """Ctrl-C / SIGTERM: stop every goal and finish the MCAP file (called by run_node)."""
        # the walking goal sees the context gone at its next check; wait for it so that the node
        # is not destroyed under it
        self.turns.close(timeout_s=5.0)
        self.recording.stop()

    def _on_forget(self, request, response):
        if self.turns.walking:
            response.success, response.message = False, 'a goal is being pursued; cancel it first'
        elif self.repertoire is None:
            response.success, response.message = False, self.problem
        else:
            dead = sorted(servo for on_leg in self.known.servos.values() for servo in on_leg)
            named, self.named = self.named, None
            self.known.forget()
            self.policy = self._policy()
            response.success = True
            response.message = (
                'what was learned about the damage is dropped'
                + (f', and the reports of dead servos {dead}' if dead else '')
                + (f', and the damage the operator named ({named.label})' if named else '')
            )
        return response


def main(args: list[str] | None = None) -> int:
    """Entry point of ``ros2 run hexapod_navigation navigate_node``."""
    return run_node(NavigateNode, args, num_threads=6, parameters=PARAMETERS)


if __name__ == '__main__':
    sys.exit(main())
