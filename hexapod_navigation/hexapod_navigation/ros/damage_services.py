# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
navigate_node's damage interface: servo reports, ``~/set_known_damage``, ``~/forget``.

The bridge's dead-servo reports, the operator's word (any kind of damage) and forgetting both;
what they mean is :class:`~hexapod_navigation.core.damage_knowledge.DamageKnowledge`'s.
"""

from __future__ import annotations

from hexapod_adapt import damage_of_request
from hexapod_adapt.ros import ServoReports
from hexapod_msgs.msg import ServoFailure
from hexapod_msgs.srv import SetLegFailure
from rclpy.callback_groups import CallbackGroup
from std_srvs.srv import Trigger


class DamageServices:
    """Mixed into navigate_node: it has ``damage``, ``turns``, ``repertoire`` and ``policy``."""

    def serve_damage(self, robot: bool, work: CallbackGroup) -> None:
        """Create the services, and on the robot the subscription to the servo reports."""
        if robot:
            self.servo_reports = ServoReports(
                self, self.bridge_name, self._on_servo_failure, self._refuse_report
            )
        self.create_service(Trigger, '~/forget', self._on_forget, callback_group=work)
        self.create_service(
            SetLegFailure, '~/set_known_damage', self._on_set_known_damage, callback_group=work
        )

    def _refuse_report(self, msg: ServoFailure, why: str) -> None:
        self.get_logger().error(f'servo {msg.servo_id} (leg {msg.leg}) reported dead: {why}')

    def _on_servo_failure(self, msg: ServoFailure) -> None:
        note = self.damage.servo_report(int(msg.servo_id), int(msg.leg), str(msg.joint))
        self.get_logger().warning(note)

    def _on_set_known_damage(self, request, response):
        try:
            named = damage_of_request(request)
        except ValueError as exc:
            response.success, response.message = False, f'bad request: {exc}'
            return response
        response.message = self.damage.operator_says(named)
        damage = self.damage.damage()
        response.success = True
        response.failed_legs = list(damage.failed_legs) if damage else []
        response.damage = damage.label if damage else ''
        self.get_logger().warning(response.message)
        return response

    def _on_forget(self, request, response):
        if self.turns.walking:
            response.success, response.message = False, 'a goal is being pursued; cancel it first'
        elif self.repertoire is None:
            response.success, response.message = False, self.problem
        else:
            dropped = self.damage.forget()
            self.policy = self.damage.policy(self.repertoire)
            response.success = True
            response.message = 'what was learned about the damage is dropped' + dropped
        return response
