#!/usr/bin/env python3
# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The damaged tripod's factor study: the control tripod in S0-S2 on PyBullet, one change at a time.

studies/engines/README.md, "The damaged tripod against the thesis's simulator", holds its output.

    python scripts/pybullet_factors.py

Each row is a variant of the engine as it was before the study (friction 1.0 on ground and
feet, velocity feed-forward), or the study's outcome (position targets only). Collisions not
fatal, speeds along the walking direction, the mean (min, max) over each scenario's orientations.
The rows' frictions are per surface, as the study set them; Bullet multiplies the two, and
SimConfig.friction is the product (the coefficient where a foot meets the floor), so a row passes
its square.
"""

from __future__ import annotations

import math

from hexapod_gait import preset
from hexapod_sim import evaluate_gait, SimConfig
from hexapod_sim.engine_settings import PyBulletSettings
import hexapod_sim.physics.pybullet_engine as engine
from hexapod_sim.physics.pybullet_engine import PyBulletSimulator
from hexapod_sim.scenarios import scenario
import hexapod_sim.simulator as simulator
import numpy as np
import pybullet as p


class Variant(PyBulletSimulator):
    """The PyBullet engine with the study's switches (class attributes)."""

    feed_forward = True  # send the table's joint velocities as targets (the engine before)
    motor_max_velocity = False  # pass the URDF velocity limit to the motor (the thesis code)
    tibia_deg = -165.0  # failure pose tibia angle
    rigid_failed_legs = False  # hold failed legs with a stiff velocity motor (the thesis code)

    def prepare_rows(self, positions, velocities):
        rows = super().prepare_rows(positions, velocities)
        v = np.clip(np.atleast_2d(velocities), -self.max_velocity, self.max_velocity)
        return rows, v[:, self._active_slots].tolist()

    def apply_row(self, rows, index):
        rows, v = rows
        kw = {'targetVelocities': v[index]} if self.feed_forward else {}
        if self.motor_max_velocity:
            limits = {j: lim.velocity for j, lim in zip(self.joint_indices, self.model.limits)}
            for j, q, f in zip(self._active_joints, rows.q[index], self._active_efforts):
                p.setJointMotorControl2(
                    self.body,
                    j,
                    p.POSITION_CONTROL,
                    targetPosition=q,
                    force=f,
                    maxVelocity=limits[j],
                    physicsClientId=self.client,
                )
            return
        p.setJointMotorControlArray(
            self.body,
            self._active_joints,
            p.POSITION_CONTROL,
            targetPositions=rows.q[index],
            forces=self._active_efforts,
            physicsClientId=self.client,
            **kw,
        )

    def _command_failure_pose(self):
        if not self.rigid_failed_legs:
            return super()._command_failure_pose()
        slots = [3 * (leg - 1) + k for leg in self.failed_legs for k in range(3)]
        p.setJointMotorControlArray(
            self.body,
            [self.joint_indices[s] for s in slots],
            p.VELOCITY_CONTROL,
            targetVelocities=[0.0] * len(slots),
            forces=[240.0] * len(slots),
            physicsClientId=self.client,
        )


def row(label: str, friction: float, current: bool = False, **switches) -> str:
    """Return one table row: the variant's S0-S2 speeds at ``friction`` per surface."""
    saved = engine.FAILURE_POSE
    tibia = switches.pop('tibia_deg', -165.0)
    # the failure pose is read by the reset (simulator) and by the servos holding it (engine)
    engine.FAILURE_POSE = simulator.FAILURE_POSE = (saved[0], saved[1], math.radians(tibia))
    cls = PyBulletSimulator if current else type('V', (Variant,), switches)
    try:
        # Bullet's position motor, as in the study (whatever PyBullet's default servo becomes)
        thesis_servo = PyBulletSettings(servo='position')
        config = SimConfig(engine='pybullet', friction=friction * friction, pybullet=thesis_servo)
        with cls(config) as sim:
            cells = []
            for name in ('S0', 'S1', 'S2'):
                v = [
                    evaluate_gait(
                        preset('control'), sim, collisions_fatal=False, failed_legs=legs
                    ).speed
                    for legs in scenario(name)
                ]
                cells.append(f'{np.mean(v):+.3f} ({min(v):+.3f}, {max(v):+.3f})')
    finally:
        engine.FAILURE_POSE = simulator.FAILURE_POSE = saved
    return f'| {label} | ' + ' | '.join(cells) + ' |'


def main() -> None:
    print('| variant | S0 | S1 | S2 |\n|---|---|---|---|')
    for line in (
        row('before (friction 1.0, feed-forward)', 1.0),
        row('failed legs held at tibia -150 deg', 1.0, tibia_deg=-150.0),
        row('failed legs locked rigidly', 1.0, rigid_failed_legs=True),
        row(
            'velocity limit passed to the motor', 1.0, feed_forward=False, motor_max_velocity=True
        ),
        row('position targets only', 1.0, feed_forward=False),
        row('friction 0.7', 0.7),
        row('friction 0.6', 0.6),
        row('friction 0.8', 0.8),
        row('friction 0.9', 0.9),
        row(
            'after: friction 0.7 and position targets only (the engine 2026-11-22 to 11-27)',
            0.7,
            current=True,
        ),
    ):
        print(line, flush=True)


if __name__ == '__main__':
    main()
