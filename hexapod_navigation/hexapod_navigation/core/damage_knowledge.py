# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
What navigate knows of the damage between goals: the servo reports and the operator's word.

The operator's word (``~/set_known_damage``) wins over the servo reports; either is favoured
among the damage bank's hypotheses from the next goal (``prior_reported``), and what was learned
before it is dropped then (:attr:`DamageKnowledge.changed`). ROS-free: navigate_node hands it the
reports and requests and logs what it says.
"""

from __future__ import annotations

from hexapod_adapt import KnownDamage
from hexapod_navigation.core.config import NavigationConfig
from hexapod_navigation.core.planner import RepertoirePolicy
from hexapod_navigation.core.repertoire import Repertoire
from hexapod_navigation.core.step_bank import reported_note, StepBank
from hexapod_sim.damage import Damage


class DamageKnowledge:
    """The servo reports and the operator's word, and the policy a goal starts from."""

    def __init__(self, config: NavigationConfig, bank: StepBank | None) -> None:
        self.config, self.bank = config, bank
        self.reports = KnownDamage()  # robot mode: the bridge's servo reports
        self.named: Damage | None = None  # the operator's word
        self.changed = False  # something was told since the last policy was made

    def damage(self) -> Damage | None:
        """Return the damage the next goal starts from: the operator's, else the reports'."""
        return self.named if self.named is not None else self.reports.servo_damage()

    def policy(self, repertoire: Repertoire) -> RepertoirePolicy:
        """Return a fresh policy that favours the known damage (and note it as used)."""
        self.changed = False
        return RepertoirePolicy.with_bank(repertoire, self.config, self.bank, self.damage())

    def servo_report(self, servo: int, leg: int, joint: str) -> str:
        """Take a dead-servo report from the bridge; return the sentence for the log."""
        said = self.reports.from_servo(servo, leg, joint)
        self.changed = True
        if self.named is not None:
            return f'{said}; the damage the operator named, {self.named.label}, still wins'
        note = reported_note(self.bank, self.reports.servo_damage(), self.config.prior_reported)
        return f'{said}; {note}'

    def operator_says(self, named: Damage | None) -> str:
        """Take the operator's word (None drops it); return the answer for the request."""
        self.named = named
        self.changed = True
        if named is None:
            note = reported_note(self.bank, self.damage(), self.config.prior_reported)
            return f'the damage the operator named is dropped; {note}'
        note = reported_note(self.bank, named, self.config.prior_reported)
        return f'{named.label}, as the operator says: {note}'

    def forget(self) -> str:
        """Drop the reports and the operator's word; return what was dropped, for the answer."""
        dead = sorted(servo for on_leg in self.reports.servos.values() for servo in on_leg)
        named, self.named = self.named, None
        self.reports.forget()
        self.changed = True
        return (f', and the reports of dead servos {dead}' if dead else '') + (
            f', and the damage the operator named ({named.label})' if named else ''
        )
