# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Step maps (the ``navigation`` map kind): gaits indexed by where one execution takes the body.

How such a map is made and measured (ROS-free); the navigator's view of one is
:class:`hexapod_navigation.core.repertoire.Repertoire`.

As in reset-free trial and error (Chatzilygeroudis, Vassiliades and Mouret 2018), each elite is
an omnidirectional gait (34-gene ``omni/v1`` genotype) and its niche is the body's displacement
(x, y) in its start frame after one execution of :data:`STEP_DURATION` seconds from rest. The
fitness is minus the heading change: of the gaits that reach a place, the one that keeps its
heading wins. (RTE rewards the heading of the circular arc to the end point, which suits a robot
that must face where it goes; a hexapod crab-walks, so the heading that fits any path is the one
it started with.)

Descriptors are scaled to [0, 1]: (x, y) / (2 REACH) + 0.5, clipped at the border.
"""

from __future__ import annotations

from dataclasses import dataclass
import hashlib
import math
from pathlib import Path
import time
from typing import Any

from hexapod_adapt.mapping.simulation import DEFAULT_MAP_ENGINE, worker_simulator
from hexapod_description import urdf_path
from hexapod_gait import DEFAULT_PERIOD, GaitParameters, preset, PRESETS, SIM_RATE, stance_mask
from hexapod_gait.parameters import from_omni_genotype, OMNI_MAPPING_VERSION, to_omni_genotype
from hexapod_sim import SimConfig, validate_engine
from hexapod_sim.evaluation import Displacement, evaluate_displacements
import numpy as np

#: Seconds of one gait execution: the repertoire's descriptor and the navigator's step. Two gait
#: cycles: short enough to correct the course often, long enough to walk a cycle after the start.
STEP_DURATION = 2.0
#: Half the side of the descriptor square [m]: 0.44 m/s, the fastest map gait, covers 0.88 m.
REACH = 1.0
#: Crab angles the preset gaits are tried at first (--with-presets): eight directions.
PRESET_DIRECTIONS = tuple(k * np.pi / 4 for k in range(-3, 5))


def to_descriptor(x: float | np.ndarray, y: float | np.ndarray) -> np.ndarray:
    """Return the descriptor (..., 2) in [0, 1] of displacements [m] (clipped at REACH)."""
    d = np.stack([np.asarray(x, dtype=float), np.asarray(y, dtype=float)], axis=-1)
    return np.clip(d / (2.0 * REACH) + 0.5, 0.0, 1.0)


def from_descriptor(descriptor: np.ndarray) -> np.ndarray:
    """Return the displacements (..., 2) [m] of descriptors (inverse of to_descriptor)."""
    return (np.asarray(descriptor, dtype=float) - 0.5) * 2.0 * REACH


@dataclass(frozen=True)
class StepEvaluation:
    """One repertoire candidate's evaluation (what MAP-Elites needs, and the displacement)."""

    fitness: float  # minus the heading change [rad]
    descriptor: np.ndarray  # (2,)
    valid: bool
    seconds: float  # compute time [s]
    displacement: Displacement
    peak_tilt: float = math.nan  # not recorded for a step


class SimulateSteps:
    """
    Picklable MAP-Elites evaluation function of a navigation repertoire.

    (m, 34) omni genotypes -> m :class:`StepEvaluation`, one execution of STEP_DURATION seconds
    each from rest on an intact robot, collisions fatal (as for gait maps). With
    ``min_stance_legs`` > 0, a gait with fewer feet on the ground at some instant of its cycle is
    invalid without being simulated (a repertoire a damaged robot can walk all of).
    """

    def __init__(self, engine: str = DEFAULT_MAP_ENGINE, min_stance_legs: int = 0) -> None:
        self.engine = validate_engine(engine)
        if not (isinstance(min_stance_legs, int) and 0 <= min_stance_legs <= 6):
            raise ValueError(f'min_stance_legs must be 0..6, got {min_stance_legs!r}')
        self.min_stance_legs = min_stance_legs

    def __call__(self, genes: np.ndarray) -> list[StepEvaluation]:
        genes = np.atleast_2d(genes)
        t = time.thread_time()  # CPU time: a busy machine does not inflate it
        stands = [
            self.min_stance_legs == 0
            or gait_min_stance(from_omni_genotype(g)) >= self.min_stance_legs
            for g in genes
        ]
        walked = iter(
            evaluate_displacements(
                [g for g, ok in zip(genes, stands) if ok],
                worker_simulator(self.engine),
                STEP_DURATION,
                collisions_fatal=True,
                failed_legs=(),
                decode=from_omni_genotype,
            )
        )
        few = f'fewer than {self.min_stance_legs} feet on the ground at some instant'
        moves = [
            next(walked) if ok else Displacement(0.0, 0.0, 0.0, False, few, 0.0) for ok in stands
        ]
        each = (time.thread_time() - t) / max(len(moves), 1)
        return [
            StepEvaluation(-abs(m.yaw), to_descriptor(m.x, m.y), m.valid, each, m) for m in moves
        ]


#: One cycle of the fixed period, at the simulator's rate: the instants gait_min_stance checks.
_CYCLE_TIMES = np.arange(int(round(DEFAULT_PERIOD * SIM_RATE))) / SIM_RATE


def gait_min_stance(gait: GaitParameters) -> int:
    """Return the fewest feet ``gait`` has on the ground at any instant of one cycle."""
    return int(stance_mask(gait, _CYCLE_TIMES).sum(axis=1).min())


def repertoire_fingerprint(
    engine: str = DEFAULT_MAP_ENGINE, min_stance_legs: int = 0
) -> dict[str, Any]:
    """Return what a repertoire's cells depend on besides the genes (stored in its metadata)."""
    sim = SimConfig(engine=validate_engine(engine)).fingerprint()
    fingerprint = {
        'kind': 'navigation',
        'genotype_mapping': OMNI_MAPPING_VERSION,
        'urdf_sha256': hashlib.sha256(Path(urdf_path()).read_bytes()).hexdigest(),
        'simulator': {**sim, 'collisions_fatal': True},
        'trial_duration': STEP_DURATION,
        'descriptor': {'name': 'displacement', 'reach_m': REACH},
    }
    if min_stance_legs:  # absent when 0: repertoires made before the setting keep their print
        fingerprint['min_stance_legs'] = min_stance_legs
    return fingerprint


def preset_genotypes() -> tuple[tuple[float, ...], ...]:
    """Return the preset gaits at the eight PRESET_DIRECTIONS as omni genotypes (tried first)."""
    return tuple(
        tuple(float(g) for g in to_omni_genotype(preset(name).replace(crab_angle=float(a))))
        for name in PRESETS
        for a in PRESET_DIRECTIONS
    )
