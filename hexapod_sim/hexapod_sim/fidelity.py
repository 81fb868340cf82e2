# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The fidelity table, and how well two engines agree.

The table: simulated speed of the reference gaits, intact and under each failure scenario (averaged
over its orientations), for each engine; and how well two engines agree over a set of walking
gaits. Collisions are not fatal, as in the thesis's control test and adaptation runs (5.2.2,
5.2.3).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

from hexapod_gait import preset
from hexapod_sim.evaluation import evaluate_gait, evaluate_gaits
from hexapod_sim.scenarios import scenario, SCENARIO_NAMES
from hexapod_sim.simulator import Simulator
import numpy as np
from scipy.stats import spearmanr


@dataclass(frozen=True)
class FidelityRow:
    """One gait in one failure scenario on one engine, averaged over its orientations."""

    engine: str
    gait: str
    scenario: str
    orientations: int
    mean_speed: float  # m/s along the walking direction
    min_speed: float
    max_speed: float


@dataclass(frozen=True)
class Agreement:
    """How two engines agree over the same gaits (collisions not fatal)."""

    gaits: int
    spearman: float  # rank correlation of fitness
    mean_abs_descriptor: float  # mean |duty factor difference| over gaits and legs
    speeds_a: np.ndarray  # (gaits,) m/s on engine a
    speeds_b: np.ndarray  # (gaits,) m/s on engine b


def fidelity_rows(sim: Simulator) -> list[FidelityRow]:
    """Return the control gait in S0-S4 and the wave and quadruped presets intact, on ``sim``."""
    rows = []
    plan = [('control', name) for name in SCENARIO_NAMES] + [('wave', 'S0'), ('quadruped', 'S0')]
    for gait_name, scen in plan:
        speeds = [
            evaluate_gait(preset(gait_name), sim, collisions_fatal=False, failed_legs=legs).speed
            for legs in scenario(scen)
        ]
        rows.append(
            FidelityRow(
                sim.engine,
                gait_name,
                scen,
                len(speeds),
                float(np.mean(speeds)),
                min(speeds),
                max(speeds),
            )
        )
    sim.set_failed_legs(())
    return rows


def agreement(genotypes: Sequence[np.ndarray], sim_a: Simulator, sim_b: Simulator) -> Agreement:
    """
    Compare two engines over ``genotypes``.

    Spearman correlation of fitness and mean absolute descriptor difference (use walking gaits,
    e.g. a map's elites: random feasible gaits mostly stand still, and their ranking is noise).
    """
    a = evaluate_gaits(list(genotypes), sim_a, collisions_fatal=False)
    b = evaluate_gaits(list(genotypes), sim_b, collisions_fatal=False)
    va, vb = np.array([r.speed for r in a]), np.array([r.speed for r in b])
    da, db = np.array([r.descriptor for r in a]), np.array([r.descriptor for r in b])
    return Agreement(len(a), float(spearmanr(va, vb)[0]), float(np.abs(da - db).mean()), va, vb)


def markdown(rows: list[FidelityRow]) -> str:
    """Return the rows as a markdown table: one speed column per engine."""
    engines = list(dict.fromkeys(r.engine for r in rows))
    keyed = {(r.engine, r.gait, r.scenario): r for r in rows}
    plan = list(dict.fromkeys((r.gait, r.scenario, r.orientations) for r in rows))
    head = (
        '| gait | scenario | orientations | '
        + ' | '.join(f'{e} mean (m/s) | {e} min | {e} max' for e in engines)
        + ' |'
    )
    lines = [head, '|' + '---|' * (3 + 3 * len(engines))]
    for gait, scen, n in plan:
        cells = []
        for e in engines:
            r = keyed[(e, gait, scen)]
            cells.append(f'{r.mean_speed:.3f} | {r.min_speed:.3f} | {r.max_speed:.3f}')
        lines.append(f'| {gait} | {scen} | {n} | ' + ' | '.join(cells) + ' |')
    return '\n'.join(lines)
