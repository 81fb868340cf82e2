"""The fidelity table: simulated speed of the reference gaits, intact and under each failure
scenario (averaged over its orientations). Collisions are not fatal, as in the thesis's
control test and adaptation runs (5.2.2, 5.2.3)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hexapod_gait import preset
from hexapod_sim.evaluation import evaluate_gait
from hexapod_sim.scenarios import SCENARIO_NAMES, scenario
from hexapod_sim.simulator import HexapodSimulator


@dataclass(frozen=True)
class FidelityRow:
    gait: str
    scenario: str
    orientations: int
    mean_speed: float   # m/s along the walking direction
    min_speed: float
    max_speed: float


def fidelity_rows(sim: HexapodSimulator) -> list[FidelityRow]:
    rows = []
    plan = [("control", name) for name in SCENARIO_NAMES] + [("wave", "S0"), ("quadruped", "S0")]
    for gait_name, scen in plan:
        speeds = [evaluate_gait(preset(gait_name), sim, collisions_fatal=False, failed_legs=legs).speed
                  for legs in scenario(scen)]
        rows.append(FidelityRow(gait_name, scen, len(speeds), float(np.mean(speeds)), min(speeds), max(speeds)))
    sim.set_failed_legs(())
    return rows


def markdown(rows: list[FidelityRow]) -> str:
    lines = ["| gait | scenario | orientations | mean speed (m/s) | min | max |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r.gait} | {r.scenario} | {r.orientations} | {r.mean_speed:.3f} | "
                     f"{r.min_speed:.3f} | {r.max_speed:.3f} |")
    return "\n".join(lines)
