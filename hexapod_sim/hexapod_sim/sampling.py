"""Seeded samplers of random gaits: reachable genotypes, and feasible ones (reachable and
valid in a map-generation evaluation: no self-collision, no body touching the ground)."""
from __future__ import annotations

import numpy as np

from hexapod_gait import GENOTYPE_SIZE, ReachabilityError, build_joint_table, from_genotype
from hexapod_gait.trajectory import reachable_key_points
from hexapod_sim.evaluation import EvaluationResult, evaluate_gaits
from hexapod_sim.simulator import Simulator

_BATCH = 256


def random_reachable_genes(rng: np.random.Generator, max_draws: int = 100_000) -> np.ndarray:
    """One uniform random genotype whose key points the legs can reach (a vectorised check of
    microseconds). About 2.4 % of uniform genotypes pass it and only ~0.03 % are feasible gaits,
    so drawing MAP-Elites' random initialisation from this subset saves ~97 % of the wasted
    evaluations of thesis-style uniform initialisation without biasing among feasible gaits.
    Raises RuntimeError if ``max_draws`` uniform draws hold none."""
    for _ in range(max(1, max_draws // _BATCH)):
        batch = rng.random((_BATCH, GENOTYPE_SIZE))
        ok = np.flatnonzero(reachable_key_points(batch))
        if ok.size:
            return batch[ok[0]]
    raise RuntimeError(f"no reachable genotype in {max_draws} draws")


def random_reachable_genotypes(n: int, seed: int) -> np.ndarray:
    """(n, 32) random genotypes whose whole gait cycle the controller can follow: key points
    reachable (:func:`random_reachable_genes`) and every sample of the cycle too."""
    rng = np.random.default_rng(seed)
    found: list[np.ndarray] = []
    while len(found) < n:
        genes = random_reachable_genes(rng)
        try:
            build_joint_table(from_genotype(genes))
        except ReachabilityError:
            continue
        found.append(genes)
    return np.array(found).reshape(n, GENOTYPE_SIZE)


def random_feasible_genotypes(n: int, seed: int, sim: Simulator,
                              max_candidates: int = 1_000_000) -> tuple[np.ndarray, list[EvaluationResult]]:
    """(n, 32) random genotypes that are valid map-generation gaits on ``sim``, with their
    evaluations. Raises RuntimeError if max_candidates reachable genotypes yield fewer."""
    rng_seed = seed
    kept: list[np.ndarray] = []
    results: list[EvaluationResult] = []
    tried = 0
    while len(kept) < n:
        batch = random_reachable_genotypes(64, rng_seed)
        for genes, result in zip(batch, evaluate_gaits(list(batch), sim, collisions_fatal=True)):
            tried += 1
            if result.valid:
                kept.append(genes)
                results.append(result)
                if len(kept) == n:
                    break
        rng_seed += 1_000_003
        if tried >= max_candidates and len(kept) < n:
            raise RuntimeError(f"only {len(kept)} feasible gaits in {tried} reachable candidates")
    return np.array(kept), results
