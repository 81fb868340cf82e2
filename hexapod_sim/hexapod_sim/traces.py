# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A gait walked with its body's path, attitude and foot contacts recorded (any engine).

An evaluation keeps what a map needs (distance, duty factors, peak tilt). A diagnosis needs the
whole trial: where the body went, how it rolled and pitched through the gait cycle, which feet
touched. :func:`trace_gait` walks one gait from standing, as :func:`~hexapod_sim.evaluation.
evaluate_gait` does (same table, same reset, collisions not fatal, as adaptation trials), and
samples the body every ``every`` steps.
"""

from __future__ import annotations

from dataclasses import dataclass

from hexapod_description import N_LEGS
from hexapod_gait import build_joint_table, from_genotype, GaitParameters, ReachabilityError
from hexapod_sim.damage import Damage
from hexapod_sim.evaluation import GaitLike, TRIAL_DURATION
from hexapod_sim.simulator import Simulator
import numpy as np


@dataclass(frozen=True)
class GaitTrace:
    """
    One walk, sampled.

    ``t`` (n,) s from the gait's start; the body's ``position`` (n, 3) m and ``quaternion``
    (n, 4) (x, y, z, w) in the world frame; the feet's ``contacts`` (n, 6); the ``gait``.
    """

    t: np.ndarray
    position: np.ndarray
    quaternion: np.ndarray
    contacts: np.ndarray
    gait: GaitParameters

    def __post_init__(self) -> None:
        n = len(self.t)
        shapes = {'position': (n, 3), 'quaternion': (n, 4), 'contacts': (n, N_LEGS)}
        for name, shape in shapes.items():
            got = np.shape(getattr(self, name))
            if got != shape:
                raise ValueError(f'{name} must have shape {shape}, got {got}')


def trace_gait(
    gait: GaitLike,
    sim: Simulator,
    damage: Damage | None = None,
    duration: float = TRIAL_DURATION,
    every: int = 4,
) -> GaitTrace | None:
    """
    Walk ``gait`` (or a genotype) on ``sim`` under ``damage`` (None: as the simulator is).

    Returns its trace sampled every ``every`` steps (the first sample one ``every`` after the
    start), or None if the gait cannot be played (unreachable, invalid). The damage is kept.
    A contact sample is whether the foot touched in any step since the previous sample.
    """
    if every < 1:
        raise ValueError(f'every must be at least 1 step, got {every}')
    try:
        g = gait if isinstance(gait, GaitParameters) else from_genotype(gait)
        table = build_joint_table(g, rate=1.0 / sim.dt)
    except (ReachabilityError, ValueError):
        return None
    if damage is not None:
        sim.set_damage(damage)
    n_steps = int(round(duration / sim.dt))
    rows = sim.prepare_rows(table.positions, table.velocities)
    n_rows = len(table.positions)
    sim.reset(table.positions[0])
    n = n_steps // every
    t, position = np.empty(n), np.empty((n, 3))
    quaternion, contacts = np.empty((n, 4)), np.zeros((n, N_LEGS), dtype=bool)
    touched = np.zeros(N_LEGS, dtype=bool)
    for k in range(n * every):
        sim.apply_row(rows, k % n_rows)
        touched |= np.asarray(sim.step().contacts, dtype=bool)
        if (k + 1) % every == 0:
            i = (k + 1) // every - 1
            t[i] = (k + 1) * sim.dt
            position[i], quaternion[i] = sim.base_pose()
            contacts[i], touched = touched, np.zeros(N_LEGS, dtype=bool)
    return GaitTrace(t, position, quaternion, contacts, g)
