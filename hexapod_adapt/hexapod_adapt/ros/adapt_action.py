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
from typing import Callable

from hexapod_msgs.action import Adapt
from hexapod_util.ros_glue import ACTION_QOS, unless_closing
import rclpy
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.action.server import ServerGoalHandle
from rclpy.callback_groups import CallbackGroup
from rclpy.node import Node

#: s a goal ending at shutdown waits for the executor to stop, and the shutdown for the goal.
SHUTDOWN_WAIT_S = 5.0
BUSY = 'adapt goal rejected: an adaptation is already running (adapt_node runs one at a time)'


def goal_end(cancelled: bool, success: bool) -> str:
    """Return the goal handle's call that ends a run: ``canceled``, ``succeed`` or ``abort``."""
    return 'canceled' if cancelled else 'succeed' if success else 'abort'


class AdaptServer:
    """
    ``node``'s ``adapt`` action: ``run_goal(handle, result)`` runs one accepted goal.

    ``busy`` is held from a goal's acceptance to its end; the node's shutdown calls
    :meth:`end_goals` after its executor has stopped.
    """

    def __init__(
        self,
        node: Node,
        run_goal: Callable[[ServerGoalHandle, Adapt.Result], None],
        work: CallbackGroup,
    ) -> None:
        self.node, self.run_goal = node, run_goal
        self.busy = threading.Lock()
        self.spin_ended = threading.Event()  # set by the node's shutdown, after its executor
        self.server = ActionServer(
            node,
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
        self.node.get_logger().warning(BUSY)
        return GoalResponse.REJECT

    def _execute(self, handle: ServerGoalHandle) -> Adapt.Result:
        result = Adapt.Result(best_archive_index=-1)
        try:
            self.run_goal(handle, result)
        finally:
            self.busy.release()
        if rclpy.ok(context=self.node.context):
            end = goal_end(handle.is_cancel_requested, result.success)
        else:  # shutting down: nobody can be told, the goal's state is set quietly
            end = 'abort'
            # returned while the executor still spins, the result would be sent on a context
            # that is gone (a warning, and rcl's "publisher's context is invalid" line)
            self.spin_ended.wait(SHUTDOWN_WAIT_S)
        unless_closing(self.node, getattr(handle, end))
        return result

    def end_goals(self) -> None:
        """At shutdown, after the executor: let the goal in progress end, quietly (5 s at most)."""
        self.spin_ended.set()
        if self.busy.acquire(timeout=SHUTDOWN_WAIT_S):
            self.busy.release()
