# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A node's health on ``/diagnostics``, as rqt_robot_monitor, Foxglove and the aggregator read it.

A node hands :class:`DiagnosticsPublisher` a function that returns its :class:`Health` list (one
per part: a servo, the radio link, the IMU, the simulator, the map, the job in progress); the
publisher sends them as one ``diagnostic_msgs/DiagnosticArray`` every ``period`` seconds, and at
once when the node calls :meth:`DiagnosticsPublisher.publish_now` after a change.
"""

from __future__ import annotations

from typing import Callable, Mapping

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from hexapod_util.health import Health, OK
import rclpy
from rclpy._rclpy_pybind11 import RCLError
from rclpy.node import Node

TOPIC = '/diagnostics'
PERIOD_S = 1.0


def status_msg(node_name: str, health: Health) -> DiagnosticStatus:
    """Return ``health`` as a DiagnosticStatus named ``<node>: <part>``."""
    return DiagnosticStatus(
        level=bytes([health.level]),
        name=f'{node_name}: {health.name}',
        message=health.message,
        hardware_id=health.hardware_id,
        values=[KeyValue(key=k, value=str(v)) for k, v in health.values.items()],
    )


class DiagnosticsPublisher:
    """Publish a node's :class:`Health` list on ``/diagnostics`` (see the module docstring)."""

    def __init__(
        self, node: Node, health: Callable[[], list[Health]], period: float = PERIOD_S
    ) -> None:
        self.node, self.health = node, health
        self.pub = node.create_publisher(DiagnosticArray, TOPIC, 10)
        node.create_timer(period, self.publish_now)

    def publish_now(self) -> None:
        """Publish every part's health now (after a change; the timer calls it too)."""
        if not rclpy.ok(context=self.node.context):
            return  # shutting down: there is no one to tell, and the publisher is gone
        name = self.node.get_name()
        msg = DiagnosticArray(status=[status_msg(name, h) for h in self.health()])
        msg.header.stamp = self.node.get_clock().now().to_msg()
        try:
            self.pub.publish(msg)
        except RCLError:  # the context closed in between
            if rclpy.ok(context=self.node.context):
                raise


class StatusHealth:
    """A node whose health is one part's last status (a simulator, a job): on ``/diagnostics``."""

    def __init__(
        self,
        node: Node,
        name: str,
        hardware_id: str,
        values: Callable[[], Mapping[str, str]] = dict,
        message: str = 'starting',
    ) -> None:
        self.name, self.hardware_id, self.values = name, hardware_id, values
        self.level, self.message = OK, message
        self.publisher = DiagnosticsPublisher(node, self.health)

    def health(self) -> list[Health]:
        """Return the part's last status, with its current values."""
        return [Health(self.name, self.level, self.message, self.hardware_id, self.values())]

    def update(self, level: int | bytes, message: str) -> None:
        """Take a new status (a DiagnosticStatus level or its byte) and publish it at once."""
        self.level = level[0] if isinstance(level, bytes) else int(level)
        self.message = message
        self.publisher.publish_now()
