# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Judge the reports on ``servo_failures``: believed only when the configured bridge confirms them.

rclpy does not tell a subscriber which publisher sent a message, and a forger that publishes one
report and leaves at once is gone from the graph by the time its message is handled. So each
report is checked with the bridge (``<bridge>/get_servo_failures``: the servos it holds dead), and
the topic's publishers are watched, to name a sender that is not the bridge. Naming is the graph's
best: a sender that leaves at once is often gone before the graph learns its node's name (then
the refusal says so).
"""

from __future__ import annotations

import queue
import threading
import time

from hexapod_adapt.online.prior import servo_report_verdict
from hexapod_adapt.ros.graph_port import qualified, UNKNOWN_NODE
from hexapod_msgs.msg import ServoFailure
from hexapod_msgs.srv import GetServoFailures
from hexapod_util.ros_glue import EVENTS
import rclpy
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from rclpy.node import Node

#: s between looks at the publishers of servo_failures (to name a sender that leaves at once).
WATCH_S = 0.005
#: s a refused report waits for a sender's node name to reach the graph (one not seen before).
NAME_WAIT_S = 1.0
#: s to wait for the bridge's answer to "which servos are dead".
ASK_TIMEOUT_S = 3.0


class ServoReports:
    """Believe (``believe(msg)``) the servo reports the bridge confirms; ``refuse`` the others."""

    def __init__(self, node: Node, bridge_name: str, believe, refuse) -> None:
        self.node, self.bridge = node, qualified(node, bridge_name)
        self.believe, self.refuse = believe, refuse
        self.seen: dict[str, float] = {}  # publisher of the topic -> when last seen (monotonic)
        self._lock = threading.Lock()
        self.client = node.create_client(
            GetServoFailures,
            f'{self.bridge}/get_servo_failures',
            callback_group=ReentrantCallbackGroup(),
        )
        self.topic = node.resolve_topic_name('servo_failures')
        # each report is judged in a thread of its own, one at a time, in arrival order: the
        # subscription only queues it. Judged in the executor (a mutually exclusive group, busy
        # while a report waits for the bridge), one acknowledged report of 20 was never handed
        # to the callback (CI, 2026-12-02; rclcpp#832 describes the same executor pattern).
        self._reports: queue.Queue[ServoFailure | None] = queue.Queue()
        node.create_subscription(
            ServoFailure,
            'servo_failures',
            self._reports.put,
            EVENTS,
            callback_group=MutuallyExclusiveCallbackGroup(),
        )
        self._closed = threading.Event()
        threading.Thread(target=self._judge, daemon=True, name='servo_report_judge').start()
        # rclpy does not say who sent a message, and a sender may leave at once: the graph is
        # watched often enough to see who joins (its own thread: a busy executor is too late)
        threading.Thread(target=self._watch, daemon=True, name='servo_report_senders').start()

    def _judge(self) -> None:
        """Judge the queued reports in arrival order, until :meth:`close`."""
        while (msg := self._reports.get()) is not None:
            try:
                self._on_report(msg)
            except Exception as exc:  # noqa: BLE001 - one report's failure must not stop the rest
                if not rclpy.ok(context=self.node.context):
                    return  # the node is closing: its client and graph are gone
                self.node.get_logger().error(f'servo report {msg.servo_id} not judged: {exc}')

    def _watch(self) -> None:
        """Look at the topic's publishers every WATCH_S s, in a thread of its own."""
        while not self._closed.wait(WATCH_S):
            try:
                self._note_publishers()
            except Exception:  # noqa: BLE001 - the node is closing: its graph is gone
                if not rclpy.ok(context=self.node.context):
                    return

    def _note_publishers(self) -> None:
        """Remember the topic's publishers whose node the graph names now."""
        infos = self.node.get_publishers_info_by_topic(self.topic)
        now = time.monotonic()
        with self._lock:
            for i in infos:
                if i.node_name != UNKNOWN_NODE:
                    self.seen[f'{i.node_namespace.rstrip("/")}/{i.node_name}'] = now

    def close(self) -> None:
        """Stop watching the graph and judging reports (those still queued are dropped)."""
        self._closed.set()
        self._reports.put(None)

    def others(self) -> list[str]:
        """
        Return the publishers of the topic other than the bridge seen since the last report.

        Forgotten once judged, so each refusal names who joined for it (and who stays).
        """
        self._note_publishers()
        with self._lock:
            names = sorted(n for n in self.seen if n != self.bridge)
            self.seen.clear()
        return names

    def confirmed(self, servo: int) -> bool | None:
        """Whether the bridge holds ``servo`` dead (None: it did not answer)."""
        if not self.client.wait_for_service(timeout_sec=ASK_TIMEOUT_S):
            return None
        done = threading.Event()
        future = self.client.call_async(GetServoFailures.Request())
        future.add_done_callback(lambda _: done.set())
        if not done.wait(ASK_TIMEOUT_S) or future.result() is None:
            return None
        return any(f.servo_id == servo for f in future.result().failures)

    def await_check(self, timeout: float, alive) -> tuple[int, str, list[ServoFailure]]:
        """
        Ask the bridge until its check of every servo is done or cannot be, ``timeout`` s at most.

        Returns (GetServoFailures' CHECK_*, its status in words, the servos it holds dead).
        ``alive()`` false (shutting down, the goal cancelled) ends the wait at once.
        """
        deadline = time.monotonic() + timeout
        answer = (GetServoFailures.Response.CHECK_PENDING, 'bridge_node did not answer', [])
        while alive() and time.monotonic() < deadline:
            if self.client.service_is_ready():
                future = self.client.call_async(GetServoFailures.Request())
                asked = time.monotonic()
                while not future.done() and alive() and time.monotonic() - asked < ASK_TIMEOUT_S:
                    time.sleep(0.02)
                if future.done() and future.result() is not None:
                    r = future.result()
                    answer = (int(r.check), r.check_status, list(r.failures))
                    if r.check != GetServoFailures.Response.CHECK_PENDING:
                        return answer
            time.sleep(0.1)
        return answer

    def _on_report(self, msg: ServoFailure) -> None:
        servo = int(msg.servo_id)
        confirmed, others = self.confirmed(servo), set(self.others())
        first, deadline = set(others), time.monotonic() + NAME_WAIT_S
        # a refused report waits for a name the graph did not hold yet: a new process's node
        # name reaches the graph after its data (names seen before may be an earlier sender's)
        while not confirmed and not others - first and time.monotonic() < deadline:
            time.sleep(0.02)
            others |= set(self.others())
        verdict = servo_report_verdict(servo, confirmed, self.bridge, sorted(others))
        if verdict:
            self.refuse(msg, verdict)
        else:
            self.believe(msg)
