# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Gait evaluation for MAP-Elites and adaptation (thesis 4.1.1, 4.1.2, 4.1.4, 4.2.5, 5.2.2).

genotype or gait -> (fitness, descriptor):
  fitness    = distance travelled by the base along the walking direction in ``duration``
               seconds [m] (the crab angle in base_link; the robot starts at the origin, yaw 0);
  descriptor = per-leg fraction of time steps with the foot on the ground (eq. 4.2).
With ``collisions_fatal`` (map generation) a self-collision or a non-foot link touching the
ground ends the evaluation with the failure value; without it (adaptation, 5.2.2) they are
only counted. An unreachable gait also gets the failure value, and so does one that ends with
the body upside down (a fall: the robot's IMU sees it; PyBullet can slide a robot on its back
metres in a trial). The failure value is the thesis's: fitness 0, descriptor all zeros, with
``valid`` False and a reason.

Works on any engine through :class:`~hexapod_sim.simulator.Simulator`; :func:`evaluate_gaits`
hands a whole batch to the engine at once (MuJoCo runs it natively in C).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
import math
from typing import Callable, Sequence

from hexapod_description import N_LEGS
from hexapod_gait import build_joint_table, from_genotype, GaitParameters, ReachabilityError
from hexapod_sim.damage import Damage
from hexapod_sim.simulator import JointRows, PlayResult, quat_to_euler, Simulator, upside_down
import numpy as np

TRIAL_DURATION = 5.0  # s (thesis 4.1.1)
FAILURE_FITNESS = 0.0
#: Version of the scoring rules: results cached under another version are not this code's
#: (2: a gait that ends upside down scores FAILURE_FITNESS).
EVALUATION_VERSION = 2
#: The reason of a gait that ends with the body upside down: a fall, whatever it travelled.
FELL_OVER = 'fell over: the body ended upside down'

GaitLike = GaitParameters | Sequence[float] | np.ndarray


@dataclass(frozen=True)
class EvaluationResult:
    """The outcome of one evaluation; the one result type from the simulator to the archive."""

    fitness: float  # m along the walking direction (FAILURE_FITNESS if invalid)
    descriptor: np.ndarray  # (6,) duty factor per leg, 0..1 (zeros if invalid)
    valid: bool
    reason: str  # why it is invalid; empty if valid
    duration: float  # simulated seconds
    collision_steps: int = 0  # steps with a collision (collisions not fatal)
    contacts: np.ndarray | None = None  # (steps, 6) measured foot contacts, if recorded
    seconds: float = 0.0  # compute time of this evaluation [s] (for utilisation figures)
    peak_tilt: float = 0.0  # rad: the largest |roll| or |pitch| (if recorded, else 0)

    @property
    def speed(self) -> float:
        """Average speed along the walking direction [m/s]."""
        return self.fitness / self.duration if self.duration > 0 else 0.0


def failure(reason: str, duration: float) -> EvaluationResult:
    """Return the thesis's failure value with a reason."""
    return EvaluationResult(FAILURE_FITNESS, np.zeros(N_LEGS), False, reason, duration)


@dataclass(frozen=True)
class _Played:
    """One gait's rollout, or why it never ran (the shared first half of every evaluation)."""

    gait: GaitParameters | None
    play: PlayResult | None
    reason: str  # why it is invalid ('' if it played without an engine failure)


def _play_gaits(
    gaits: Sequence[GaitLike],
    sim: Simulator,
    duration: float,
    collisions_fatal: bool,
    failed_legs: Sequence[int] | Damage | None,
    record_contacts: bool,
    decode: Callable[[Sequence[float]], GaitParameters],
    record_tilt: bool = False,
) -> tuple[int, list[_Played]]:
    if not math.isfinite(duration) or duration <= 0:
        raise ValueError(f'duration must be a positive number of seconds, got {duration!r}')
    if failed_legs is not None:
        sim.set_damage(failed_legs)
    n_steps = int(round(duration / sim.dt))
    if n_steps < 1:
        raise ValueError(f'duration {duration!r} s is shorter than one time step ({sim.dt:g} s)')
    out: list[_Played | None] = [None] * len(gaits)
    params: list[GaitParameters] = []
    tables: list[JointRows] = []
    slots: list[int] = []
    for i, gait in enumerate(gaits):
        try:
            g = gait if isinstance(gait, GaitParameters) else decode(gait)
            table = build_joint_table(g, rate=1.0 / sim.dt)
        except ReachabilityError as exc:
            out[i] = _Played(None, None, f'unreachable: {exc}')
            continue
        except ValueError as exc:
            out[i] = _Played(None, None, f'invalid: {exc}')
            continue
        params.append(g)
        tables.append(JointRows(table.positions, table.velocities))
        slots.append(i)
    played = sim.rollout(
        tables,
        n_steps,
        stop_on_collision=collisions_fatal,
        record_contacts=record_contacts,
        record_tilt=record_tilt,
    )
    for i, g, r in zip(slots, params, played):
        if r.unstable is not None:
            out[i] = _Played(g, r, r.unstable)
        elif collisions_fatal and r.first_collision is not None:
            out[i] = _Played(g, r, r.first_collision)
        else:
            out[i] = _Played(g, r, '')
    return n_steps, [p for p in out if p is not None]


def evaluate_gaits(
    gaits: Sequence[GaitLike],
    sim: Simulator,
    duration: float = TRIAL_DURATION,
    collisions_fatal: bool = True,
    failed_legs: Sequence[int] | Damage | None = None,
    record_contacts: bool = False,
    record_tilt: bool = False,
) -> list[EvaluationResult]:
    """
    Evaluate gaits (or 32-gene genotypes) on ``sim``, one result each, in order.

    Deterministic for a given input. ``failed_legs`` (if given: leg numbers to lift, or a
    :class:`~hexapod_sim.damage.Damage`) is applied first and kept. ``record_tilt``: each result's
    ``peak_tilt`` (a fall that ends upside down keeps it too).
    """
    n_steps, played = _play_gaits(
        gaits,
        sim,
        duration,
        collisions_fatal,
        failed_legs,
        record_contacts,
        from_genotype,
        record_tilt=record_tilt,
    )
    results = []
    for p in played:
        if p.reason:
            results.append(failure(p.reason, duration))
            continue
        g, r = p.gait, p.play
        if r.final_orientation is not None and upside_down(r.final_orientation):
            results.append(replace(failure(FELL_OVER, duration), peak_tilt=r.peak_tilt))
            continue
        direction = (math.cos(g.crab_angle), math.sin(g.crab_angle))
        fitness = float(r.final_position[0] * direction[0] + r.final_position[1] * direction[1])
        results.append(
            EvaluationResult(
                fitness,
                r.contact_steps.astype(float) / n_steps,
                True,
                '',
                duration,
                r.collision_steps,
                r.contacts,
                peak_tilt=r.peak_tilt,
            )
        )
    return results


@dataclass(frozen=True)
class Displacement:
    """
    Where one execution of a gait from rest took the body, in its start frame.

    The start frame is the robot at the origin, yaw 0 (every rollout starts there).
    """

    x: float  # m
    y: float  # m
    yaw: float  # heading change [rad], in (-pi, pi]
    valid: bool
    reason: str  # why it is invalid; empty if valid
    duration: float  # simulated seconds
    collision_steps: int = 0
    peak_tilt: float = 0.0  # rad: the largest of |roll| and |pitch| during the execution


def evaluate_displacements(
    gaits: Sequence[GaitLike],
    sim: Simulator,
    duration: float,
    collisions_fatal: bool = True,
    failed_legs: Sequence[int] | Damage | None = None,
    decode: Callable[[Sequence[float]], GaitParameters] = from_genotype,
) -> list[Displacement]:
    """
    Play each gait (or genotype, read with ``decode``) for ``duration`` s from rest.

    One :class:`Displacement` each, in order; invalid gaits (unreachable, colliding when
    ``collisions_fatal``, unstable physics) carry zeros and the reason. Deterministic.
    """
    _, played = _play_gaits(
        gaits, sim, duration, collisions_fatal, failed_legs, False, decode, record_tilt=True
    )
    out = []
    for p in played:
        if p.reason:
            out.append(Displacement(0.0, 0.0, 0.0, False, p.reason, duration))
            continue
        r = p.play
        _, _, yaw = quat_to_euler(r.final_orientation)
        out.append(
            Displacement(
                float(r.final_position[0]),
                float(r.final_position[1]),
                float(yaw),
                True,
                '',
                duration,
                r.collision_steps,
                r.peak_tilt,
            )
        )
    return out


def evaluate_gait(
    gait: GaitLike,
    sim: Simulator,
    duration: float = TRIAL_DURATION,
    collisions_fatal: bool = True,
    failed_legs: Sequence[int] | Damage | None = None,
    record_contacts: bool = False,
    record_tilt: bool = False,
) -> EvaluationResult:
    """Evaluate one gait (or 32-gene genotype) on ``sim``; deterministic for a given input."""
    return evaluate_gaits(
        [gait], sim, duration, collisions_fatal, failed_legs, record_contacts, record_tilt
    )[0]
