# Copyright 2026 Hexapod adaptation team
# All rights reserved.
#
# Permission is hereby granted, free of charge, to any person obtaining a copy
# of this software and associated documentation files (the "Software"), to deal
# in the Software without restriction, including without limitation the rights
# to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
# copies of the Software, and to permit persons to whom the Software is
# furnished to do so, subject to the following conditions:
#
# The above copyright notice and this permission notice shall be included in all
# copies or substantial portions of the Software.
#
# THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
# IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
# FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
# AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
# LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
# OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
# SOFTWARE.
"""
The steered tripod: the firmware's control tripod in its eight crab directions.

What the robot can always walk, damaged or not: the navigation baseline
(:class:`hexapod_navigation.planner.SteeredTripod`) and an option of the repertoire planner.
:func:`tripod_cycles` measures one cycle of each direction under damage, for the step bank.
"""

from __future__ import annotations

import math

from hexapod_gait import GaitParameters, preset
from hexapod_sim.damage import Damage
from hexapod_sim.evaluation import evaluate_displacements
from hexapod_sim.simulator import Simulator
import numpy as np

#: The firmware's eight crab directions (robot-facts.md, movement frame), in base_link.
FIRMWARE_DIRECTIONS = tuple(k * math.pi / 4 for k in range(8))


def wrap_angle(a: float) -> float:
    """Return ``a`` [rad] wrapped into (-pi, pi]."""
    return math.pi - (math.pi - a) % (2.0 * math.pi)


def tripod_gaits() -> list[GaitParameters]:
    """Return the control tripod in each firmware crab direction (index = direction 0..7)."""
    base = preset('control')
    return [base.replace(crab_angle=wrap_angle(a)) for a in FIRMWARE_DIRECTIONS]


def tripod_cycles(sim: Simulator, damage: Damage | None) -> np.ndarray:
    """
    Return each direction's second cycle from rest under ``damage`` (None: intact), (8, 3).

    Each (dx, dy, dyaw) in the frame the robot had when the cycle began. The second cycle,
    because the navigator walks tripod cycles back to back (the first is within 3 % of it,
    intact). Deterministic.
    """
    gaits = tripod_gaits()
    period = gaits[0].period
    damage = damage if damage is not None else Damage()  # None would keep the sim's damage
    one = evaluate_displacements(gaits, sim, period, collisions_fatal=False, failed_legs=damage)
    two = evaluate_displacements(
        gaits, sim, 2 * period, collisions_fatal=False, failed_legs=damage
    )
    out = np.zeros((len(gaits), 3))
    for k, (a, b) in enumerate(zip(one, two)):
        if not (a.valid and b.valid):
            continue  # an unstable rollout: no motion (the cycle is learned as it is walked)
        c, s = math.cos(a.yaw), math.sin(a.yaw)
        dx, dy = b.x - a.x, b.y - a.y
        out[k] = (c * dx + s * dy, -s * dx + c * dy, wrap_angle(b.yaw - a.yaw))
    return out
