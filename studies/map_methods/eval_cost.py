# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Where a MuJoCo evaluation's time goes, and which cheaper settings keep the map's ranking.

Issue 30, deliverable 2. 2,000 gaits of the default map (seeded sample of its elites) are
evaluated as map generation evaluates them (5 s, intact, collisions fatal, batches of 8, one
process) with today's settings and with each candidate; a candidate keeps the ranking when the
Spearman correlation of the fitness is >= 0.98 and the top-100 sets overlap by >= 95 %. The
time per evaluation is measured on one core (run it on a quiet machine).

    python -m studies.map_methods.eval_cost [--gaits 2000] \
        > studies/map_methods/results/eval_cost.txt
"""

from __future__ import annotations

import argparse
from dataclasses import replace
import sys
import time

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
from hexapod_sim import create_simulator, evaluate_gaits, SimConfig
from hexapod_sim.engine_settings import DEFAULT_SETTINGS
import numpy as np
from scipy.stats import spearmanr

#: The candidates: (name, settings), each one change from today's.
CANDIDATES = (
    ('today', DEFAULT_SETTINGS),
    ('tolerance 1e-6', replace(DEFAULT_SETTINGS, tolerance=1e-6)),
    ('tolerance 1e-4', replace(DEFAULT_SETTINGS, tolerance=1e-4)),
    ('iterations 5', replace(DEFAULT_SETTINGS, iterations=5)),
    ('iterations 2', replace(DEFAULT_SETTINGS, iterations=2)),
    ('solver cg', replace(DEFAULT_SETTINGS, solver='cg')),
    ('integrator euler', replace(DEFAULT_SETTINGS, integrator='euler')),
    # the gait tables follow the step (one row per step): fewer, longer steps
    ('time step 1/160', replace(DEFAULT_SETTINGS, time_step=1 / 160)),
    ('time step 1/120', replace(DEFAULT_SETTINGS, time_step=1 / 120)),
)
BATCH = 8


def evaluate(genes: np.ndarray, settings) -> tuple[np.ndarray, np.ndarray, float]:
    """Return (fitness, valid, seconds per evaluation) of ``genes`` under ``settings``."""
    with create_simulator(SimConfig(engine='mujoco', mujoco=settings)) as sim:
        evaluate_gaits(list(genes[:BATCH]), sim, collisions_fatal=True, failed_legs=())  # warm
        t0 = time.perf_counter()
        results = []
        for i in range(0, len(genes), BATCH):
            results += evaluate_gaits(
                list(genes[i : i + BATCH]), sim, collisions_fatal=True, failed_legs=()
            )
        seconds = (time.perf_counter() - t0) / len(genes)
    fitness = np.array([r.fitness if r.valid else -np.inf for r in results])
    return fitness, np.array([r.valid for r in results]), seconds


def main(argv: list[str] | None = None) -> int:
    """Print each candidate's cost and ranking against today's settings."""
    ap = argparse.ArgumentParser(prog='eval_cost', description=__doc__.split('\n\n')[0])
    ap.add_argument('--gaits', type=int, default=2000)
    ap.add_argument('--seed', type=int, default=0)
    args = ap.parse_args(argv)
    archive = load_archive(shipped_map(DEFAULT_MAP))
    rng = np.random.default_rng(args.seed)
    chosen = rng.choice(archive.elite_indices(), args.gaits, replace=False)
    genes = archive.genotypes[chosen]
    print(f'{args.gaits} default-map elites (seed {args.seed}), batches of {BATCH}, one process')
    print(f'{"setting":18s} {"ms/eval":>8s} {"valid":>6s} {"spearman":>9s} {"top-100":>8s}')
    reference = None
    for name, settings in CANDIDATES:
        fitness, valid, seconds = evaluate(genes, settings)
        if reference is None:
            reference = fitness
        both = np.isfinite(reference) & np.isfinite(fitness)
        rho = spearmanr(reference[both], fitness[both]).statistic if both.sum() > 2 else np.nan
        top = len(set(np.argsort(-reference)[:100]) & set(np.argsort(-fitness)[:100]))
        print(
            f'{name:18s} {seconds * 1e3:8.2f} {int(valid.sum()):6d} {rho:9.4f} {top:7d}%',
            flush=True,
        )
    return 0


if __name__ == '__main__':
    sys.exit(main())
