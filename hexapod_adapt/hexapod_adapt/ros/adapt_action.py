# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
adapt_node's ``adapt`` action server: one goal at a time, a cancel at once.

A goal sent while one runs is rejected (the only reason a goal is rejected; the node logs it); a
goal that cannot run is accepted and aborted at once with the reason in its result. The goal ends
SUCCEEDED when M-BOA's rule was met, CANCELED when cancelled, ABORTED otherwise (the result still
holds the best gait found).
"""

from __future__ import annotations

import threading

from hexapod_msgs.action import Adapt
from hexapod_util.ros_glue import ACTION_QOS, unless_closing
import rclpy
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.callback_groups import CallbackGroup

#: s a goal ending at shutdown waits for the executor to stop, and the shutdown for the goal.
SHUTDOWN_WAIT_S = 5.0
BUSY = 'adapt goal rejected: an adaptation is already running (adapt_node runs one at a time)'


def goal_end(cancelled: bool, success: bool) -> str:
    """Return the goal handle's call that ends a run: ``canceled``, ``succeed`` or ``abort``."""
    return 'canceled' if cancelled else 'succeed' if success else 'abort'


class AdaptAction:
    """Mixed into adapt_node: it has ``_adapt(handle, result)``, which runs one goal."""

    def serve_adapt(self, work: CallbackGroup) -> None:
        """Serve the ``adapt`` action; ``busy`` is held from a goal's acceptance to its end."""
        self.busy = threading.Lock()
        self.spin_ended = threading.Event()  # set by the node's shutdown, after its executor
        self.server = ActionServer(
            self,
            Adapt,
            'adapt',
            execute_callback=self._execute,
            goal_callback=self._on_goal,
            cancel_callback=lambda _: CancelResponse.ACCEPT,
            callback_group=work,
            **ACTION_QOS,
        )

    def _on_goal(self, goal) -> GoalResponse:
        if self.busy.acquire(blocking=False):  # never waits: every goal is answered at once
            return GoalResponse.ACCEPT
        self.get_logger().warning(BUSY)
        return GoalResponse.REJECT

    def _execute(self, handle) -> Adapt.Result:
        result = Adapt.Result(best_archive_index=-1)
        try:
            self._adapt(handle, result)
        finally:
            self.busy.release()
        if rclpy.ok(context=self.context):
            end = goal_end(handle.is_cancel_requested, result.success)
        else:  # shutting down: nobody can be told, the goal's state is set quietly
            end = 'abort'
            # returned while the executor still spins, the result would be sent on a context
            # that is gone (a warning, and rcl's "publisher's context is invalid" line)
            self.spin_ended.wait(SHUTDOWN_WAIT_S)
        unless_closing(self, getattr(handle, end))
        return result

    def end_goals(self) -> None:
        """At shutdown, after the executor: let the goal in progress end, quietly (5 s at most)."""
        self.spin_ended.set()
        if self.busy.acquire(timeout=SHUTDOWN_WAIT_S):
            self.busy.release()
