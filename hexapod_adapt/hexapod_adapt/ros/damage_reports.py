# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
adapt_node's damage reports: the simulator's ``sim/damage``, the bridge's ``servo_failures``.

What they mean (and ``~/forget``) is :class:`~hexapod_adapt.online.prior.KnownDamage`'s; a
servo report is believed only when the configured bridge_node confirms it
(:mod:`hexapod_adapt.ros.servo_reports`).
"""

from __future__ import annotations

from typing import Callable

from hexapod_adapt.online.adaptation import TrialAborted
from hexapod_adapt.online.prior import KnownDamage
from hexapod_adapt.online.run_messages import RunRequest
from hexapod_adapt.ros.servo_reports import ServoReports
from hexapod_msgs.msg import LegDamage, ServoFailure
from hexapod_msgs.srv import GetServoFailures
from hexapod_sim.damage import Damage
from hexapod_util.ros_glue import LATCHED
from rclpy.callback_groups import CallbackGroup
from rclpy.node import Node
from std_srvs.srv import Trigger

#: How long a robot run waits for bridge_node's start-up check of every servo [s].
SERVO_CHECK_WAIT_S = 10.0


class DamageReports:
    """
    What ``node``'s peers say is broken: ``known`` holds it, for the runs to take.

    Sim mode: the simulator's latched ``sim/damage``. Robot and manual modes: ``servo_failures``,
    believed only when ``bridge_name`` confirms it, and the bridge's start-up servo check
    (:meth:`servo_check`). ``~/forget`` is refused while ``busy()`` (a run is going on).
    """

    def __init__(
        self,
        node: Node,
        mode: str,
        bridge_name: str,
        busy: Callable[[], bool],
        work: CallbackGroup,
    ) -> None:
        self.node, self.mode, self.busy = node, mode, busy
        self.known = KnownDamage()
        self.servo_reports: ServoReports | None = None
        if mode == 'sim':
            node.create_subscription(LegDamage, 'sim/damage', self.on_sim_damage, LATCHED)
        else:
            self.servo_reports = ServoReports(
                node, bridge_name, self._on_servo_failure, self._refuse_report
            )
        node.create_service(Trigger, '~/forget', self._on_forget, callback_group=work)

    def on_sim_damage(self, msg: LegDamage) -> None:
        """Take the simulator's damage (its latched topic, or its get_damage answer)."""
        legs, kinds, strengths = list(msg.failed_legs), list(msg.kinds), list(msg.strengths)
        self.node.get_logger().info(self.known.from_sim(legs, kinds, strengths, list(msg.joints)))

    def at_start(
        self,
        run: RunRequest,
        alive: Callable[[], bool],
        tell: Callable[[str], None],
        sim_damage: Callable[[float], LegDamage | None],
        timeout: float,
    ) -> tuple[str, Damage | None, str]:
        """
        Return (the servo check's outcome, damage, its source) as ``run`` starts.

        ``run.auto``: the damage is whatever is reported now. On the robot the bridge's servo
        check comes first; in sim mode ``sim_damage(timeout)`` asks the simulator what it holds
        (a SetLegFailure just before the request may not have arrived on sim/damage yet), and
        TrialAborted says it did not answer.
        """
        if not run.auto:
            return '', run.damage, run.source
        check = ''
        if self.mode == 'sim':
            now = sim_damage(timeout)
            if now is None:
                raise TrialAborted(
                    f'sim_node did not say its damage (get_damage) in {timeout:g} s'
                    ' (is sim_node running?)'
                )
            self.on_sim_damage(now)
        else:
            check = self.servo_check(alive, tell)
        return (check, *self.known.for_run(None, False))

    def servo_check(self, alive: Callable[[], bool], tell: Callable[[str], None]) -> str:
        """
        Wait (bounded) for bridge_node's check of every servo; take its reports; say how it went.

        Before a robot run chooses blind or the prior, so that a servo dead at start-up is known
        before the first trial. ``alive()`` False ends the wait (a cancel, a shutdown).
        """
        reports = self.servo_reports
        check, status, failures = reports.await_check(1.0, alive)
        if check == GetServoFailures.Response.CHECK_PENDING:
            tell(
                f"waiting for bridge_node's check of every servo ({status}; up to"
                f' {SERVO_CHECK_WAIT_S:g} s)'
            )
            check, status, failures = reports.await_check(SERVO_CHECK_WAIT_S, alive)
        for msg in failures:  # the bridge's own answer: confirmed
            self._on_servo_failure(msg)
        dead = ', '.join(f'servo {f.servo_id} (leg {f.leg} {f.joint})' for f in failures)
        if check == GetServoFailures.Response.CHECK_DONE:
            return f'servo check: {status}; ' + (f'dead: {dead}' if dead else 'none dead')
        return f'no servo check ({status}): a dead servo may be unknown' + (
            f'; reported dead: {dead}' if dead else ''
        )

    def _refuse_report(self, msg: ServoFailure, why: str) -> None:
        self.node.get_logger().error(f'servo {msg.servo_id} (leg {msg.leg}) reported dead: {why}')

    def _on_servo_failure(self, msg: ServoFailure) -> None:
        said = self.known.from_servo(int(msg.servo_id), int(msg.leg), str(msg.joint))
        self.node.get_logger().warning(said)

    def _on_forget(self, request, response):
        if self.busy():
            response.success, response.message = False, 'an adaptation is running; cancel it first'
        else:
            response.success, response.message = True, self.known.forget()
            if self.mode == 'sim':
                response.message += ' (in sim mode the simulator reports the damage it has)'
        return response
