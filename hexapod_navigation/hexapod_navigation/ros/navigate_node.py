# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``ros2 run hexapod_navigation navigate_node``: walk to a place after damage, learning on the way.

Serves the ``navigate`` action (hexapod_msgs/Navigate), modelled on nav2's NavigateToPose: a goal
in ``odom`` is pursued step by step over the navigation repertoire with the learned correction
(:mod:`hexapod_navigation.core`), through gait_node + sim_node (``mode:=sim``) or bridge_node
(``mode:=robot``), with no resets. An invalid goal is rejected with the reason; a new goal
preempts the one being walked; a cancel stops the robot within one gait cycle; a PoseStamped on
``goal_pose`` (RViz's "2D Goal Pose") is sent as a goal. What was learned
about the damage, the bridge's dead-servo reports and the operator's word
(``~/set_known_damage``) carry from goal to goal; ``~/forget`` drops them. docs/navigation.md
says more.
"""

from __future__ import annotations

import math
import sys

from diagnostic_msgs.msg import DiagnosticStatus
from geometry_msgs.msg import PoseStamped
from hexapod_adapt import OdomLog, SampleLog, TrialAborted, Waiter
from hexapod_adapt.ros import (
    GraphPort,
    RECORDED_TYPES,
    RecordedTopics,
    RunRecording,
)
from hexapod_msgs.action import Navigate
from hexapod_navigation.core.config import goal_problem
from hexapod_navigation.core.damage_knowledge import DamageKnowledge
from hexapod_navigation.core.episode import BodyFailure, Feedback, run_episode
from hexapod_navigation.core.loading import load_navigation
from hexapod_navigation.core.repertoire import shipped_repertoire
from hexapod_navigation.core.specialists import shipped_specialists
from hexapod_navigation.core.step_bank import shipped_step_bank
from hexapod_navigation.ros import navigate_msgs as conv
from hexapod_navigation.ros import node_settings as settings
from hexapod_navigation.ros.bodies import PoseLog
from hexapod_navigation.ros.damage_services import DamageServices
from hexapod_navigation.ros.goal_turns import GoalTurns
from hexapod_navigation.ros.wiring import make_body, subscribe_poses
from hexapod_util.diagnostics import StatusHealth
from hexapod_util.guarded_logging import GuardedLogging
from hexapod_util.recording import type_name
from hexapod_util.ros_glue import (
    ACTION_QOS,
    declare,
    LATCHED,
    param_specs,
    publish_status,
    run_node,
    unless_closing,
)
import rclpy
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


class NavigateNode(DamageServices, GuardedLogging, Node):
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
        for warning, note in data.notes(self.config.use_bank, use_specialists):
            if warning:  # rclpy fixes a call site's severity: one call per severity
                self.get_logger().warning(note)
            else:
                self.get_logger().info(note)
        self.damage = DamageKnowledge(self.config, data.bank)
        self.bridge_name = values['bridge_node']
        self.policy = self.damage.policy(self.repertoire) if self.repertoire else None

        self.status_pub = self.create_publisher(DiagnosticStatus, 'navigate/status', LATCHED)
        self.health = StatusHealth(self, 'navigation', f'navigate, {self.mode} mode')
        self.marker_pub = self.create_publisher(Marker, 'navigate/goal', LATCHED)
        self.poses, self.trial_poses = PoseLog(), SampleLog()
        self.waiter = Waiter(lambda: rclpy.ok(context=self.context))
        self.recording = RunRecording(
            self.resolve_topic_name,
            lambda: self.get_clock().now().nanoseconds,
            self.get_logger().error,
        )
        peers = (values['sim_node'], values['bridge_node'])
        self.port = GraphPort(self, peers, self.waiter.until, OdomLog(), self.recording)
        self.record_dir = values['record_dir']
        # the sensor subscriptions only when recording: at sim_node's faster-than-real-time rates
        # their callbacks delayed the odometry the steps are timed by
        self.recorded = RecordedTopics(self, self.recording) if self.record_dir else None
        stop_client = self.create_client(Trigger, f'{values["bridge_node"]}/stop_trial')
        graph = conv.GraphNavigationPort(self.port, stop_client)
        self.trial_duration = values['trial_duration']
        external = subscribe_poses(self, values, self.poses, self.trial_poses)
        self.timeout = values['timeout']
        self.body = make_body(
            values, graph, self.poses, self.trial_poses, self.waiter, external,
            self.config.tip_guard,
        )  # fmt: skip
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
            **ACTION_QOS,
        )
        # RViz's "2D Goal Pose" (a PoseStamped on goal_pose) is a goal, as for nav2's navigator
        # sent from a callback of the client's own group: its answer cannot overtake the send
        own = MutuallyExclusiveCallbackGroup()
        self.own = conv.navigate_client(self, callback_group=own)
        self.create_subscription(
            PoseStamped, 'goal_pose', lambda m: self.own.send_goal_async(Navigate.Goal(pose=m)),
            10, callback_group=own,
        )  # fmt: skip
        self.serve_damage(self.mode == 'robot', work)
        if self.problem:
            self._status(DiagnosticStatus.ERROR, self.problem)
        else:
            self._status(
                DiagnosticStatus.OK,
                f'navigate_node ready: mode {self.mode}, {len(self.repertoire)} gaits in the'
                f' repertoire, pose from {values["pose_topic"] or "odom"}',
            )

    def _status(self, level: bytes, message: str) -> None:
        unless_closing(
            self, publish_status, self, self.status_pub, level, message, 'navigate_node'
        )
        unless_closing(self, self.health.update, level, message)

    # -- the action ----------------------------------------------------------------------------
    def _goal_problem(self, goal) -> str:
        """Say what is wrong with ``goal`` that can be told at once ('' if nothing yet)."""
        if self.policy is None:
            return self.problem
        x, y, problem = conv.goal_position(goal)
        problem = problem or settings.goal_settings_problem(goal.tolerance, goal.time_limit)
        if problem:
            return problem
        # before the first pose, all but the range (CI once saw a NaN goal accepted then)
        return goal_problem(x, y, self._known_pose(), self.config)

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
        x, y, _ = conv.goal_position(goal)
        return goal_problem(x, y, self._known_pose(), self.config)

    def _on_goal(self, goal) -> GoalResponse:
        problem = self._goal_problem(goal)  # never waits: every request is answered at once
        if problem:
            x, y, _ = conv.goal_position(goal)
            self._status(DiagnosticStatus.WARN, f'goal ({x}, {y}) rejected: {problem}')
            return GoalResponse.REJECT
        return GoalResponse.ACCEPT

    def _on_accepted(self, handle) -> None:
        self.turns.accepted(self._key(handle))  # the goal being walked stops at its next check
        unless_closing(self, handle.execute)

    @staticmethod
    def _key(handle) -> bytes:
        return bytes(handle.goal_id.uuid)

    def _execute(self, handle) -> Navigate.Result:
        key, goal = self._key(handle), handle.request
        x, y, _ = conv.goal_position(goal)  # its frame was checked when it came
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
            self._status(DiagnosticStatus.WARN, f'goal ({x}, {y}) aborted: {problem}')
            unless_closing(self, handle.abort)
            return Navigate.Result(outcome=Navigate.Result.FAILED, reason=problem)
        try:
            if self.damage.changed:  # what was learned before a new damage report is stale
                self.policy = self.damage.policy(self.repertoire)
            config = settings.goal_config(self.config, goal.tolerance, goal.time_limit)
            self.policy.config = config
            path = self._start_recording()
            marker = conv.goal_marker(x, y, config.tolerance, self._now())
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
                unless_closing(self, handle.publish_feedback, conv.feedback_msg(f, self._now()))

            self._status(DiagnosticStatus.OK, f'navigating to ({x:.2f}, {y:.2f})')
            try:
                result = run_episode(self.body, self.policy, (x, y), config, stopped, feedback)
            except (TrialAborted, BodyFailure) as exc:  # the graph stopped answering
                result, reason = None, str(exc)
            else:
                reason = ''

            finally:
                self.recording.stop()
            preempted = self.turns.superseded(key)
        finally:
            self.turns.done(key)
        if not rclpy.ok(context=self.context):
            return self._end(*conv.unwalked(True, False), handle)
        recording = str(path) if path else ''
        call, out = conv.ending(
            result, reason, (x, y), recording, self._now(), preempted,
            handle.is_cancel_requested,
        )  # fmt: skip
        if result is not None:
            self._status(
                DiagnosticStatus.OK if result.reached else DiagnosticStatus.WARN,
                f'goal ({x:.2f}, {y:.2f}): {out.reason} after {result.walking_time:.1f} s',
            )
        return self._end(call, out, handle)

    def _end(self, call: str, out: Navigate.Result, handle) -> Navigate.Result:
        """End the goal by the handle's ``call`` (succeed, canceled, abort); return ``out``."""
        unless_closing(self, getattr(handle, call))
        return out

    def _end_unwalked(self, handle) -> Navigate.Result:
        """End a goal that never got its turn: cancelled, superseded, or the node closing."""
        closing = not rclpy.ok(context=self.context)
        return self._end(*conv.unwalked(closing, handle.is_cancel_requested), handle)

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


def main(args: list[str] | None = None) -> int:
    """Entry point of ``ros2 run hexapod_navigation navigate_node``."""
    return run_node(NavigateNode, args, num_threads=6, parameters=PARAMETERS)


if __name__ == '__main__':
    sys.exit(main())
