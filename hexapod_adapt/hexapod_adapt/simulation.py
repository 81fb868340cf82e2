"""The hexapod side of map generation: the simulator as MAP-Elites' evaluation function, and
the fingerprint of what a map's fitness depends on. (``map_elites.py`` stays generic.)"""
from __future__ import annotations

import hashlib
import time
from pathlib import Path
from typing import Any

import numpy as np

from hexapod_description import urdf_path
from hexapod_gait import GENOTYPE_MAPPING_VERSION
from hexapod_sim import SimConfig, Simulator, create_simulator, evaluate_gaits, validate_engine
from hexapod_sim.evaluation import TRIAL_DURATION, EvaluationResult

#: Engine used for maps unless told otherwise: MuJoCo, ~7x cheaper per evaluation than PyBullet.
DEFAULT_MAP_ENGINE = "mujoco"

_WORKER_SIMS: dict[str, Simulator] = {}


def worker_simulator(engine: str) -> Simulator:
    """This process's simulator for ``engine``, created on first use and reused (a worker
    process evaluates many batches)."""
    sim = _WORKER_SIMS.get(engine)
    if sim is None:
        sim = _WORKER_SIMS[engine] = create_simulator(SimConfig(engine=validate_engine(engine)))
    return sim


class SimulateGenotypes:
    """Picklable MAP-Elites evaluation function: (m, 32) genotypes -> m results, evaluated as
    one batch in the worker's simulator, collisions fatal (thesis 4.2.5)."""

    def __init__(self, engine: str = DEFAULT_MAP_ENGINE) -> None:
        self.engine = validate_engine(engine)

    def __call__(self, genes: np.ndarray) -> list[EvaluationResult]:
        genes = np.atleast_2d(genes)
        t = time.perf_counter()
        results = evaluate_gaits(list(genes), worker_simulator(self.engine), collisions_fatal=True)
        each = (time.perf_counter() - t) / max(len(results), 1)
        return [EvaluationResult(r.fitness, r.descriptor, r.valid, r.reason, r.duration, r.collision_steps,
                                 None, each) for r in results]


def simulation_fingerprint(engine: str = DEFAULT_MAP_ENGINE) -> dict[str, Any]:
    """What a map's fitness depends on besides the genes: the URDF, the engine and its settings,
    the genotype mapping and the trial duration. Stored in the archive's metadata."""
    sim = SimConfig(engine=validate_engine(engine)).fingerprint()
    return {"genotype_mapping": GENOTYPE_MAPPING_VERSION,
            "urdf_sha256": hashlib.sha256(Path(urdf_path()).read_bytes()).hexdigest(),
            "simulator": {**sim, "collisions_fatal": True},
            "trial_duration": TRIAL_DURATION}


def archive_engine(metadata: dict[str, Any]) -> str | None:
    """The engine that made an archive, from its metadata (None if it does not say)."""
    simulator = metadata.get("simulator")
    engine = simulator.get("engine") if isinstance(simulator, dict) else None
    return engine if isinstance(engine, str) else None
