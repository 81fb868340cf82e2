"""Seeded samplers of random gaits: reachable genotypes, and feasible ones (reachable and
valid in a map-generation evaluation: no self-collision, no body touching the ground)."""
from __future__ import annotations

import numpy as np

from hexapod_gait import GENOTYPE_SIZE, ReachabilityError, build_joint_table, from_genotype
from hexapod_gait.trajectory import reachable_key_points
from hexapod_sim.evaluation import EvaluationResult, evaluate_gait
from hexapod_sim.simulator import HexapodSimulator

_CHUNK = 20000


def random_reachable_genotypes(n: int, seed: int) -> np.ndarray:
    """(n, 32) uniform random genotypes whose gait the controller can follow."""
    rng = np.random.default_rng(seed)
    found: list[np.ndarray] = []
    while len(found) < n:
        batch = rng.random((_CHUNK, GENOTYPE_SIZE))
        for genes in batch[reachable_key_points(batch)]:
            try:
                build_joint_table(from_genotype(genes))
            except ReachabilityError:
                continue
            found.append(genes)
            if len(found) == n:
                break
    return np.array(found)


def random_feasible_genotypes(n: int, seed: int, sim: HexapodSimulator,
                              max_candidates: int = 1_000_000) -> tuple[np.ndarray, list[EvaluationResult]]:
    """(n, 32) random genotypes that are valid map-generation gaits on ``sim``, with their
    evaluations. Raises RuntimeError if max_candidates reachable genotypes yield fewer."""
    rng_seed = seed
    kept: list[np.ndarray] = []
    results: list[EvaluationResult] = []
    tried = 0
    while len(kept) < n:
        for genes in random_reachable_genotypes(256, rng_seed):
            tried += 1
            result = evaluate_gait(genes, sim, collisions_fatal=True)
            if result.valid:
                kept.append(genes)
                results.append(result)
                if len(kept) == n:
                    break
        rng_seed += 1_000_003
        if tried >= max_candidates:
            raise RuntimeError(f"only {len(kept)} feasible gaits in {tried} reachable candidates")
    return np.array(kept), results
