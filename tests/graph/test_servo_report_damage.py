# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""A dead servo, from the robot's report to the damage the prior and the simulator use."""

from __future__ import annotations

from hexapod_adapt.online.prior import KnownDamage
from hexapod_bridge.protocol.extension import MIRRORED_LEG_MAP
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
