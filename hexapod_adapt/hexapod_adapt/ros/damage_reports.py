# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
adapt_node's damage reports: the simulator's ``sim/damage``, the bridge's ``servo_failures``.

What they mean (and ``~/forget``) is :class:`~hexapod_adapt.online.prior.KnownDamage`'s; a
servo report is believed only when the configured bridge_node confirms it
(:mod:`hexapod_adapt.ros.servo_reports`).
"""

from __future__ import annotations

from hexapod_adapt.online.prior import KnownDamage
from hexapod_adapt.ros.servo_reports import ServoReports
from hexapod_msgs.msg import LegDamage, ServoFailure
from hexapod_util.ros_glue import LATCHED
from rclpy.callback_groups import CallbackGroup
from std_srvs.srv import Trigger


class DamageReports:
    """Mixed into adapt_node: it has ``mode``, ``busy`` and ``_param``."""

    def listen_for_damage(self, work: CallbackGroup) -> None:
        """Subscribe to the mode's damage reports and serve ``~/forget``."""
        self.known = KnownDamage()
        if self.mode == 'sim':
            self.create_subscription(LegDamage, 'sim/damage', self._on_sim_damage, LATCHED)
        else:
            self.servo_reports = ServoReports(
                self, self._param('bridge_node'), self._on_servo_failure, self._refuse_report
            )
        self.create_service(Trigger, '~/forget', self._on_forget, callback_group=work)

    def _on_sim_damage(self, msg: LegDamage) -> None:
        legs, kinds, strengths = list(msg.failed_legs), list(msg.kinds), list(msg.strengths)
        self.get_logger().info(self.known.from_sim(legs, kinds, strengths, list(msg.joints)))

    def _refuse_report(self, msg: ServoFailure, why: str) -> None:
        self.get_logger().error(f'servo {msg.servo_id} (leg {msg.leg}) reported dead: {why}')

    def _on_servo_failure(self, msg: ServoFailure) -> None:
        said = self.known.from_servo(int(msg.servo_id), int(msg.leg), str(msg.joint))
        self.get_logger().warning(said)

    def _on_forget(self, request, response):
        if self.busy.locked():
            response.success, response.message = False, 'an adaptation is running; cancel it first'
        else:
            response.success, response.message = True, self.known.forget()
            if self.mode == 'sim':
                response.message += ' (in sim mode the simulator reports the damage it has)'
        return response
