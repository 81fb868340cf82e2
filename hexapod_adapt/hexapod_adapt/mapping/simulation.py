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
The hexapod side of map generation.

The simulator as MAP-Elites' evaluation function, and the fingerprint of what a map's fitness
depends on. (``map_elites.py`` stays generic.).
"""

from __future__ import annotations

import hashlib
from pathlib import Path
import time
from typing import Any

from hexapod_description import urdf_path
from hexapod_gait import GENOTYPE_MAPPING_VERSION
from hexapod_sim import create_simulator, evaluate_gaits, SimConfig, Simulator, validate_engine
from hexapod_sim.evaluation import EvaluationResult, TRIAL_DURATION
import numpy as np

#: Engine used for maps unless told otherwise: MuJoCo, ~7x cheaper per evaluation than PyBullet.
DEFAULT_MAP_ENGINE = 'mujoco'

_WORKER_SIMS: dict[str, Simulator] = {}


def worker_simulator(engine: str) -> Simulator:
    """
    Return this process's simulator for ``engine``, created on first use and reused.

    A worker process evaluates many batches.
    """
    sim = _WORKER_SIMS.get(engine)
    if sim is None:
        sim = _WORKER_SIMS[engine] = create_simulator(SimConfig(engine=validate_engine(engine)))
    return sim


class SimulateGenotypes:
    """
    Picklable MAP-Elites evaluation function.

    (m, 32) genotypes -> m results, evaluated as one batch in the worker's simulator, collisions
    fatal (thesis 4.2.5).
    """

    def __init__(self, engine: str = DEFAULT_MAP_ENGINE) -> None:
        self.engine = validate_engine(engine)

    def __call__(self, genes: np.ndarray) -> list[EvaluationResult]:
        genes = np.atleast_2d(genes)
        t = time.thread_time()  # CPU time: a busy machine does not inflate it
        # intact, said explicitly: the process's simulator is shared, and a ceiling computed in
        # this process (or a parent it was forked from) may have left legs failed in it
        results = evaluate_gaits(
            list(genes), worker_simulator(self.engine), collisions_fatal=True, failed_legs=()
        )
        each = (time.thread_time() - t) / max(len(results), 1)
        return [
            EvaluationResult(
                r.fitness,
                r.descriptor,
                r.valid,
                r.reason,
                r.duration,
                r.collision_steps,
                None,
                each,
            )
            for r in results
        ]


def simulation_fingerprint(engine: str = DEFAULT_MAP_ENGINE) -> dict[str, Any]:
    """
    Return what a map's fitness depends on besides the genes.

    The URDF, the engine and its settings, the genotype mapping and the trial duration. Stored in
    the archive's metadata.
    """
    sim = SimConfig(engine=validate_engine(engine)).fingerprint()
    return {
        'genotype_mapping': GENOTYPE_MAPPING_VERSION,
        'urdf_sha256': hashlib.sha256(Path(urdf_path()).read_bytes()).hexdigest(),
        'simulator': {**sim, 'collisions_fatal': True},
        'trial_duration': TRIAL_DURATION,
    }


def archive_engine(metadata: dict[str, Any]) -> str | None:
    """Return the engine that made an archive, from its metadata (None if it does not say)."""
    simulator = metadata.get('simulator')
    engine = simulator.get('engine') if isinstance(simulator, dict) else None
    return engine if isinstance(engine, str) else None
