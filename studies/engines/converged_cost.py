# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Find the cheapest MuJoCo setting that agrees with today's model at 8 steps per row (issue 66).

Issue 66, deliverable 1. The reference is today's model at 8 physics steps per 240 Hz row. Each
candidate (a number of steps per row, a solver) walks the same gaits, intact, 5 s from standing,
collisions not fatal, in batches of 8 (a map worker's batch), and is held to the reference:

- the gait sets: a map's fastest and some others at random (seed 0), one ``--set
  ARCHIVE:FASTEST:RANDOM`` each;
- the fidelity table's control tripod in S0-S4 (mean speed over each scenario's orientations);
- the cost: process time of one evaluation on one core (median of the batches).

The decision rule, fixed before the runs: a candidate passes when on every gait set the median
|speed change| is <= 0.015 m/s and the Spearman >= 0.95, and every control-tripod figure is
within 5 % of the reference. The cheapest passing candidate wins. The table also shows the
tripod rule read as 5 % of the intact speed: S2 and S4 walk near 0 m/s, where a relative change
is large for any setting (README, "Cheaper converged physics").

    python -m studies.engines.converged_cost
        --set hexapod_adapt/maps/default_map.npz:300:100
        --set hexapod_adapt/maps/demo_map.npz:8:8 [--candidates 4 3 2 2:pgs]
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass, replace
import time

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.transfer import ranked_gaits
from hexapod_sim import create_simulator, SimConfig
from hexapod_sim.engine_settings import DEFAULT_SETTINGS, MujocoSettings
from hexapod_sim.evaluation import evaluate_gaits
from hexapod_sim.fidelity import fidelity_rows
import numpy as np
from scipy.stats import spearmanr

#: The decision rule (issue 66, deliverable 1).
MAX_MEDIAN_CHANGE = 0.015  # m/s
MIN_SPEARMAN = 0.95
MAX_TRIPOD_CHANGE = 0.05  # relative
BATCH = 8
REFERENCE = '8'


@dataclass(frozen=True)
class GaitSet:
    """A map's ranked gaits (its fastest, then others at random)."""

    name: str
    genotypes: np.ndarray  # (n, 32)


def settings_of(candidate: str) -> MujocoSettings:
    """Return the settings a candidate names: 'STEPS' or 'STEPS:SOLVER'."""
    steps, _, solver = candidate.partition(':')
    settings = replace(DEFAULT_SETTINGS, substeps=int(steps))
    return replace(settings, solver=solver) if solver else settings


def gait_set(spec: str) -> GaitSet:
    """Parse 'ARCHIVE:FASTEST:RANDOM' into the map's ranked gaits."""
    path, fastest, random = spec.rsplit(':', 2)
    archive = load_archive(path)
    niches = ranked_gaits(archive, int(fastest), int(random), seed=0)
    name = f'{path.rsplit("/", 1)[-1]} {fastest}+{random}'
    return GaitSet(name, archive.genotypes[niches])


def walk(settings: MujocoSettings, genotypes: np.ndarray) -> tuple[np.ndarray, float]:
    """Return the gaits' speeds [m/s] and the median process time of one evaluation [ms]."""
    speeds, per_eval = [], []
    with create_simulator(SimConfig('mujoco', mujoco=settings)) as sim:
        for start in range(0, len(genotypes), BATCH):
            batch = list(genotypes[start : start + BATCH])
            t0 = time.process_time()
            results = evaluate_gaits(batch, sim, collisions_fatal=False)
            per_eval.append((time.process_time() - t0) / len(batch) * 1e3)
            speeds += [r.speed for r in results]
    return np.array(speeds), float(np.median(per_eval))


def tripod(settings: MujocoSettings) -> np.ndarray:
    """Return the control tripod's mean speed in S0-S4."""
    with create_simulator(SimConfig('mujoco', mujoco=settings)) as sim:
        rows = fidelity_rows(sim)
    return np.array([r.mean_speed for r in rows if r.gait == 'control'])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--set', action='append', required=True, dest='sets')
    parser.add_argument('--candidates', nargs='+', default=['4', '3', '2', '2:pgs'])
    args = parser.parse_args()
    sets = [gait_set(spec) for spec in args.sets]
    candidates = [REFERENCE, *args.candidates]
    speeds: dict[tuple[str, str], np.ndarray] = {}
    cost: dict[str, list[float]] = {c: [] for c in candidates}
    tripods = {}
    for candidate in candidates:
        settings = settings_of(candidate)
        for s in sets:
            speeds[candidate, s.name], ms = walk(settings, s.genotypes)
            cost[candidate].append(ms)
        tripods[candidate] = tripod(settings)
        print(f'{candidate}: {np.median(cost[candidate]):.1f} ms an evaluation', flush=True)
    ref_ms = float(np.median(cost[REFERENCE]))
    names = [s.name for s in sets]
    head = ' | '.join(f'{n}: median abs change, Spearman' for n in names)
    print(
        f'\n| candidate | ms an evaluation (vs 8) | {head} | tripod S0-S4: largest change, '
        'relative; of the intact speed | passes; with the tripod of the intact speed |'
    )
    print('|---' * (len(names) + 4) + '|')
    for candidate in candidates:
        cells, ok = [], True
        for n in names:
            a, b = speeds[candidate, n], speeds[REFERENCE, n]
            mad, rho = float(np.median(np.abs(a - b))), float(spearmanr(a, b).statistic)
            ok &= mad <= MAX_MEDIAN_CHANGE and rho >= MIN_SPEARMAN
            cells.append(f'{mad:.4f}, {rho:.3f}')
        ref = tripods[REFERENCE]
        delta = np.abs(tripods[candidate] - ref)
        relative, of_intact = float((delta / np.abs(ref)).max()), float(delta.max() / ref[0])
        ms = float(np.median(cost[candidate]))
        verdicts = [ok and r <= MAX_TRIPOD_CHANGE for r in (relative, of_intact)]
        print(
            f'| {candidate} | {ms:.1f} ({ms / ref_ms:.2f}) | {" | ".join(cells)} '
            f'| {100 * relative:.1f} %; {100 * of_intact:.1f} % '
            f'| {"; ".join("yes" if v else "no" for v in verdicts)} |'
        )
    print('\ncontrol tripod S0-S4 [m/s]:')
    for candidate in candidates:
        print(f'  {candidate}: ' + ' '.join(f'{v:.3f}' for v in tripods[candidate]))


if __name__ == '__main__':
    main()
