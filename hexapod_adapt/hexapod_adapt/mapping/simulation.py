# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The hexapod side of map generation.

The simulator as MAP-Elites' evaluation function, and the fingerprint of what a map's fitness
depends on. (``map_elites.py`` stays generic.).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, replace
import hashlib
import math
from pathlib import Path
import time
from typing import Any

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.mapping.robust import RobustScore
from hexapod_description import urdf_path
from hexapod_gait import GENOTYPE_MAPPING_VERSION
from hexapod_sim import create_simulator, evaluate_gaits, SimConfig, Simulator, validate_engine
from hexapod_sim.evaluation import EvaluationResult, failure, TRIAL_DURATION
from hexapod_sim.simulator import fingerprint_substeps
import numpy as np

#: Engine used for maps unless told otherwise: MuJoCo, ~7x cheaper per evaluation than PyBullet.
DEFAULT_MAP_ENGINE = 'mujoco'
#: Engine taken as the maker of a map that does not record one: maps made here before archives
#: recorded their simulator (2026-11-21) were all made on PyBullet, the only engine then. A
#: thesis map (import_thesis_map) records none either; its own simulator is none of ours.
UNRECORDED_MAP_ENGINE = 'pybullet'

_WORKER_SIMS: dict[SimConfig, Simulator] = {}


def map_sim_config(engine: str, substeps: int = 0) -> SimConfig:
    """
    Return the simulator a map is made on: ``engine`` with its default settings.

    ``substeps`` > 0 sets its physics steps per 240 Hz row (``generate_map --substeps``).
    """
    config = SimConfig(engine=validate_engine(engine))
    return config.with_substeps(substeps) if substeps else config


@dataclass(frozen=True)
class WalkGuards:
    """
    What a map gait must also do to be an elite: walk, not run (``generate_map --min-feet``).

    ``min_feet``: feet on the ground on average over the trial (the sum of the descriptor's
    duty factors; 0: any). A kinematic walker with three feet down at a time can stand on them;
    the map's fastest gaits on the engine that made it kept 2.1 and ran on impacts and flight
    phases, where contact models differ most (issue 49). ``max_tilt``: the body never tilts
    (roll or pitch) past this [rad] (pi: any).
    """

    min_feet: float = 0.0
    max_tilt: float = math.pi

    def __post_init__(self) -> None:
        if not (math.isfinite(self.min_feet) and 0.0 <= self.min_feet <= 6.0):
            raise ValueError(f'min_feet must be in [0, 6] feet, got {self.min_feet!r}')
        if not (math.isfinite(self.max_tilt) and 0.0 < self.max_tilt <= math.pi):
            raise ValueError(f'max_tilt must be in (0, pi] rad, got {self.max_tilt!r}')

    @property
    def active(self) -> bool:
        """Whether any guard applies."""
        return self.min_feet > 0.0 or self.max_tilt < math.pi

    def problem(self, result: EvaluationResult) -> str:
        """Say why a valid result fails the guards ('' if it passes)."""
        feet = float(np.sum(result.descriptor))
        if feet < self.min_feet:
            return f'{feet:.2f} feet on the ground on average, fewer than {self.min_feet:g}'
        if result.peak_tilt > self.max_tilt:
            return f'the body tilted {math.degrees(result.peak_tilt):.0f} deg, past the guard'
        return ''


def worker_simulator(engine: str, substeps: int = 0) -> Simulator:
    """
    Return this process's simulator for ``engine`` (:func:`map_sim_config`), made once, reused.

    A worker process evaluates many batches.
    """
    return config_simulator(map_sim_config(engine, substeps))


def config_simulator(config: SimConfig) -> Simulator:
    """Return this process's simulator for ``config``, made once, reused."""
    sim = _WORKER_SIMS.get(config)
    if sim is None:
        sim = _WORKER_SIMS[config] = create_simulator(config)
    return sim


class SimulateGenotypes:
    """
    Picklable MAP-Elites evaluation function.

    (m, 32) genotypes -> m results, evaluated as one batch in the worker's simulator, collisions
    fatal (thesis 4.2.5); with a :class:`RobustScore`, one batch in each physics variant, each
    gait's walks combined by the score. Each result records the body's peak tilt.
    """

    def __init__(
        self,
        engine: str = DEFAULT_MAP_ENGINE,
        guards: WalkGuards | None = None,
        substeps: int = 0,
        robust: RobustScore | None = None,
    ) -> None:
        self.engine = validate_engine(engine)
        self.guards = guards or WalkGuards()
        self.substeps = substeps
        self.robust = robust or RobustScore()
        self._configs = self.robust.configs(map_sim_config(self.engine, substeps))

    def __call__(self, genes: np.ndarray) -> list[EvaluationResult]:
        genes = np.atleast_2d(genes)
        t = time.thread_time()  # CPU time: a busy machine does not inflate it
        # intact, said explicitly: the process's simulator is shared, and a ceiling computed in
        # this process (or a parent it was forked from) may have left legs failed in it
        walks: list[list[EvaluationResult]] = [[] for _ in genes]
        alive = list(range(len(genes)))
        for config in self._configs:
            # a gait that failed in one variant fails: it walks in no further one
            results = evaluate_gaits(
                [genes[i] for i in alive],
                config_simulator(config),
                collisions_fatal=True,
                failed_legs=(),
                record_tilt=True,
            )
            for i, r in zip(alive, results, strict=True):
                walks[i].append(self._guarded(r))
            alive = [i for i in alive if walks[i][-1].valid]
        each = (time.thread_time() - t) / max(len(genes), 1)
        if not self.robust.active:
            return [replace(w[0], contacts=None, seconds=each) for w in walks]
        return [replace(self.robust.combine(w), seconds=each) for w in walks]

    def _guarded(self, r: EvaluationResult) -> EvaluationResult:
        """Return ``r``, or the thesis's failure value with the reason if it fails the guards."""
        why = self.guards.problem(r) if r.valid and self.guards.active else ''
        return failure(why, r.duration) if why else r


def simulation_fingerprint(
    engine: str = DEFAULT_MAP_ENGINE,
    guards: WalkGuards | None = None,
    substeps: int = 0,
    robust: RobustScore | None = None,
) -> dict[str, Any]:
    """
    Return what a map's fitness depends on besides the genes.

    The URDF, the engine and its settings, the genotype mapping, the trial duration, the walk
    guards and the physics variants (each only when it applies: maps made without them keep
    their fingerprint). Stored in the archive's metadata.
    """
    sim = map_sim_config(engine, substeps).fingerprint()
    out = {
        'genotype_mapping': GENOTYPE_MAPPING_VERSION,
        'urdf_sha256': hashlib.sha256(Path(urdf_path()).read_bytes()).hexdigest(),
        'simulator': {**sim, 'collisions_fatal': True},
        'trial_duration': TRIAL_DURATION,
    }
    if guards is not None and guards.active:
        out['walk_guards'] = asdict(guards)
    if robust is not None and robust.active:
        out['robust_score'] = robust.fingerprint()
    return out


def map_substeps(archive: Archive, engine: str) -> int:
    """
    Return the physics steps per row ``archive`` was made at on ``engine`` (0: the default).

    What is derived from a map's gaits on the engine that made it (its ceilings, the damage
    prior) walks them in the map's physics, whatever this library's default: a map made with
    ``generate_map --substeps 4`` is re-scored at 4. 0 when the map was made on another engine
    or does not say.
    """
    simulator = archive.metadata.get('simulator')
    if not isinstance(simulator, dict) or simulator.get('engine') != engine:
        return 0
    return fingerprint_substeps(simulator) or 0


def trial_substeps(archive: Archive, engine: str) -> int:
    """
    Return the physics steps per row at which ``archive``'s gaits are measured on ``engine``.

    On the engine that made the map, the map's own (:func:`map_substeps`); on any other, that
    engine's converged step (:meth:`SimConfig.converged`; studies/engines, "Where the engines
    differ", item 6: the defaults have not converged on fast gaits), where the map's figures on
    other physics are measured. A map that does not say its engine is taken as made on
    :data:`UNRECORDED_MAP_ENGINE` (:func:`engine_of_map`).
    """
    if engine_of_map(archive) == engine:
        return map_substeps(archive, engine)
    return SimConfig.converged(engine).engine_settings().substeps


def trial_walk_key(archive: Archive, engine: str) -> dict[str, Any]:
    """
    Return what a walk of ``archive``'s gaits on ``engine`` depends on, besides the gait.

    The engine at :func:`trial_substeps` (its settings), the URDF, the genotype mapping and the
    map's trial duration: part of the key of every file derived from such walks (ceilings, gap
    calibrations).
    """
    fp = simulation_fingerprint(engine, substeps=trial_substeps(archive, engine))
    return {
        'engine': engine,
        'settings_sha256': fp['simulator']['settings_sha256'],
        'urdf_sha256': fp['urdf_sha256'],
        'genotype_mapping': fp['genotype_mapping'],
        'trial_duration': archive.trial_duration,
    }


def map_physics(archive: Archive, engine: str) -> SimConfig:
    """Return ``engine`` as ``archive``'s gaits are walked on it (:func:`trial_substeps`)."""
    return map_sim_config(engine, trial_substeps(archive, engine))


def archive_engine(metadata: dict[str, Any]) -> str | None:
    """Return the engine that made an archive, from its metadata (None if it does not say)."""
    simulator = metadata.get('simulator')
    engine = simulator.get('engine') if isinstance(simulator, dict) else None
    return engine if isinstance(engine, str) else None


def engine_of_map(archive: Archive) -> str:
    """Return the engine that made ``archive`` (:data:`UNRECORDED_MAP_ENGINE` if unrecorded)."""
    return archive_engine(archive.metadata) or UNRECORDED_MAP_ENGINE
