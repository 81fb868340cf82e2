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


def _not_yet(area: str):
    def run() -> None:
        print(f"# no {area} benchmarks yet", file=sys.stderr)
    return run


AREAS = {"gait": bench_gait, "sim": _not_yet("sim"), "map": _not_yet("map"),
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
