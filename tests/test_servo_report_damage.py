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
"""A dead servo, from the robot's report to the damage the prior and the simulator use."""

from __future__ import annotations

from hexapod_adapt.online.prior import KnownDamage
from hexapod_bridge.extension import MIRRORED_LEG_MAP
from hexapod_bridge.reports import servo_report
from hexapod_sim import create_simulator, SimConfig
from hexapod_sim.damage import FAILURE_POSE, LegDamage
import numpy as np
import pytest


@pytest.mark.parametrize('servo', [3, 7, 11, 19])
def test_a_servo_report_becomes_that_joint_unpowered_on_the_right_leg(servo):
    # the robot numbers its legs clockwise, the URDF counter-clockwise (MIRRORED_LEG_MAP)
    report = servo_report(servo, MIRRORED_LEG_MAP)
    known = KnownDamage()
    known.from_servo(servo, report.leg, report.joint)
    damage = known.servo_damage()
    assert damage.legs == (LegDamage(report.leg, 'unpowered', joints=(report.joint,)),)
    assert report.leg == MIRRORED_LEG_MAP.index(report.robot_leg) + 1
    # the simulator folds that URDF leg with its live joints; the dead one is left free
    with create_simulator(SimConfig(engine='mujoco')) as sim:
        sim.set_damage(damage)
        sim.reset(np.zeros(18))
        q = sim.joint_states()[0]
        first = 3 * (report.leg - 1)
        dead = ('coxa', 'femur', 'tibia').index(report.joint)
        for k in range(3):
            if k != dead:
                assert q[first + k] == pytest.approx(FAILURE_POSE[k])
