"""Gait evaluation for MAP-Elites and adaptation (thesis 4.1.1, 4.1.2, 4.1.4, 4.2.5, 5.2.2).

genotype or gait -> (fitness, descriptor):
  fitness    = distance travelled by the base along the walking direction in ``duration``
               seconds [m] (the crab angle in base_link; the robot starts at the origin, yaw 0);
  descriptor = per-leg fraction of time steps with the foot on the ground (eq. 4.2).
With ``collisions_fatal`` (map generation) a self-collision or a non-foot link touching the
ground ends the evaluation with the failure value; without it (adaptation, 5.2.2) they are
only counted. An unreachable gait also gets the failure value. The failure value is the
thesis's: fitness 0, descriptor all zeros, with ``valid`` False and a reason.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
import pybullet as p

from hexapod_gait import GaitParameters, ReachabilityError, build_joint_table, from_genotype
from hexapod_sim.simulator import N_LEGS, HexapodSimulator

TRIAL_DURATION = 5.0   # s (thesis 4.1.1)
FAILURE_FITNESS = 0.0


@dataclass(frozen=True)
class EvaluationResult:
    fitness: float                # m along the walking direction (FAILURE_FITNESS if invalid)
    descriptor: np.ndarray        # (6,) duty factor per leg, 0..1 (zeros if invalid)
    valid: bool
    reason: str                   # why it is invalid; empty if valid
    duration: float               # simulated seconds
    collision_steps: int = 0      # steps with a collision (collisions not fatal)
    contacts: np.ndarray | None = None   # (steps, 6) measured foot contacts, if recorded

    @property
    def speed(self) -> float:
        """Average speed along the walking direction [m/s]."""
        return self.fitness / self.duration if self.duration > 0 else 0.0


def _failure(reason: str, duration: float) -> EvaluationResult:
    return EvaluationResult(FAILURE_FITNESS, np.zeros(N_LEGS), False, reason, duration)


def evaluate_gait(gait: GaitParameters | Sequence[float] | np.ndarray, sim: HexapodSimulator,
                  duration: float = TRIAL_DURATION, collisions_fatal: bool = True,
                  failed_legs: Sequence[int] | None = None,
                  record_contacts: bool = False) -> EvaluationResult:
    """Evaluate one gait (or 32-gene genotype) on ``sim``; deterministic for a given input."""
    if not isinstance(gait, GaitParameters):
        gait = from_genotype(gait)
    if failed_legs is not None:
        sim.set_failed_legs(failed_legs)
    try:
        table = build_joint_table(gait, rate=1.0 / sim.dt)
    except ReachabilityError as exc:
        return _failure(f"unreachable: {exc}", duration)
    except ValueError as exc:
        return _failure(f"invalid: {exc}", duration)

    positions, velocities = sim.prepare_rows(table.positions, table.velocities)
    n_rows = len(positions)
    sim.reset(table.positions[0])

    # The hot loop: bound locals, one control call, one step, one contact query per step.
    cid, body, plane = sim.client, sim.body, sim.plane
    joints, efforts = sim._active_joint_indices, sim._active_efforts
    control, step, contacts_of = p.setJointMotorControlArray, p.stepSimulation, p.getContactPoints
    position_control = p.POSITION_CONTROL
    foot_leg = sim._foot_leg
    n_steps = int(round(duration / sim.dt))
    counts = [0] * N_LEGS
    record = np.zeros((n_steps, N_LEGS), dtype=bool) if record_contacts else None
    collision_steps = 0
    for k in range(n_steps):
        row = k % n_rows
        control(body, joints, position_control, targetPositions=positions[row],
                targetVelocities=velocities[row], forces=efforts, physicsClientId=cid)
        step(physicsClientId=cid)
        touching = [False] * N_LEGS
        collided = None
        for c in contacts_of(bodyA=body, physicsClientId=cid):
            if c[2] == plane:
                leg = foot_leg.get(c[3])
                if leg is not None:
                    touching[leg] = True
                    continue
                collided = collided or f"{sim.link_name(c[3])} touched the ground"
            else:
                collided = collided or f"self-collision {sim.link_name(c[3])} / {sim.link_name(c[4])}"
        if collided is not None:
            if collisions_fatal:
                return _failure(f"{collided} at t = {(k + 1) * sim.dt:.3f} s", duration)
            collision_steps += 1
        for leg in range(N_LEGS):
            if touching[leg]:
                counts[leg] += 1
        if record is not None:
            record[k] = touching
    sim.time = n_steps * sim.dt
    pos, _ = sim.base_pose()
    direction = (math.cos(gait.crab_angle), math.sin(gait.crab_angle))
    fitness = float(pos[0] * direction[0] + pos[1] * direction[1])
    return EvaluationResult(fitness, np.array(counts, dtype=float) / n_steps, True, "", duration,
                            collision_steps, record)
