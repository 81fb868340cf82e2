#!/usr/bin/env python3
"""Benchmarks. Each figure is printed on its own line as ``BENCH <name> <value> <unit>``.

    python scripts/bench.py all|gait|sim|map|adapt|bridge
"""
from __future__ import annotations

import sys
import time

import numpy as np


def bench_gait() -> None:
    """gait_build_ms: genotype -> 240 Hz joint table (what MAP-Elites does per evaluation),
    median over feasible random genotypes after warm-up."""
    from hexapod_gait import ReachabilityError, build_joint_table, from_genotype

    rng = np.random.default_rng(1)
    feasible = []
    while len(feasible) < 200:
        g = rng.random(32)
        try:
            build_joint_table(from_genotype(g))
            feasible.append(g)
        except ReachabilityError:
            pass
    samples = []
    for _ in range(5):
        for g in feasible:
            t0 = time.perf_counter()
            build_joint_table(from_genotype(g))
            samples.append(time.perf_counter() - t0)
    print(f"BENCH gait_build_ms {np.median(samples) * 1e3:.3f} ms")
    print(f"BENCH gait_build_p95_ms {np.percentile(samples, 95) * 1e3:.3f} ms")


def bench_sim() -> None:
    """sim_eval_ms: one 5 s evaluation (reset included) of a feasible gait with the production
    engine (ACCURATE), median over 200 seeded random feasible gaits, process pinned to one core.
    sim_rank_spearman: Spearman rank correlation of the FAST engine's fitness with ACCURATE's
    over the same 200 gaits; sim_eval_fast_ms: FAST's median time."""
    import os

    from scipy.stats import spearmanr

    from hexapod_sim import ACCURATE, FAST, HexapodSimulator, SimConfig, evaluate_gait
    from hexapod_sim.sampling import random_feasible_genotypes

    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    n = int(os.environ.get("BENCH_SIM_GAITS", "200"))
    accurate = HexapodSimulator(SimConfig(engine=ACCURATE))
    fast = HexapodSimulator(SimConfig(engine=FAST))
    genotypes, _ = random_feasible_genotypes(n, seed=2024, sim=accurate)

    def timed(sim):
        times, fitness = [], []
        for genes in genotypes:
            t0 = time.perf_counter()
            fitness.append(evaluate_gait(genes, sim, collisions_fatal=True).fitness)
            times.append(time.perf_counter() - t0)
        return np.median(times) * 1e3, np.array(fitness)

    ms_accurate, f_accurate = timed(accurate)
    ms_fast, f_fast = timed(fast)
    print(f"BENCH sim_eval_ms {ms_accurate:.1f} ms")
    print(f"BENCH sim_eval_fast_ms {ms_fast:.1f} ms")
    print(f"BENCH sim_rank_spearman {spearmanr(f_accurate, f_fast)[0]:.4f} 1")
    print(f"BENCH sim_feasible_gaits {n} gaits")


def _not_yet(area: str):
    def run() -> None:
        print(f"# no {area} benchmarks yet", file=sys.stderr)
    return run


AREAS = {"gait": bench_gait, "sim": bench_sim, "map": _not_yet("map"),
         "adapt": _not_yet("adapt"), "bridge": _not_yet("bridge")}


def main(argv: list[str]) -> int:
    if len(argv) != 1 or argv[0] not in list(AREAS) + ["all"]:
        print(f"usage: bench.py {{all|{'|'.join(AREAS)}}}", file=sys.stderr)
        return 2
    for name in AREAS if argv[0] == "all" else [argv[0]]:
        AREAS[name]()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
