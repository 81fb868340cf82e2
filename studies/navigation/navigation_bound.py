# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Bounds on navigate's lifted-leg times against the intact robot's (issue 31's 1.4x).

Three measurements, none of which chooses a setting:

1. ``bound``: a lower bound on each goal's walking time with the steps navigate has (the
   repertoire's gaits that keep 3 feet down, and the steered tripod's cycles), the damage known
   exactly: the first gait's transition, then straight at the best speed toward the goal any one
   of them makes under that damage (the damage bank's own measurement). It ignores turning,
   every later transition and the cost of mixing steps to hold a line, so no planner on these
   steps beats it. Intact against the 21 lifted S1-S4 cases, on the goals of seed 100 (tuning)
   and seed 0 (the report's): the ratio of the medians is what an equally good navigator
   would get for both robots.
2. ``known``: navigate itself on the tuning goals (seed 100) with the damage all but known
   (told, and ``prior_reported`` 0.999), against its defaults: what learning the damage costs.
3. ``specialists``: the default map's fastest gait under each lifted case (its shipped ceiling),
   played for one repertoire step from rest under the damage, at its own crab angle and the
   reverse one, against the repertoire's best step in that direction: what gaits made for a
   damage would give navigation. Other crab angles are out of reach for these gaits (their feet
   leave the workspace; printed as '--').

    python -m studies.navigation.navigation_bound > studies/navigation/results/navigation_bound.txt
"""

from __future__ import annotations

import argparse
from dataclasses import replace
import math
import sys

import numpy as np

SEEDS = (100, 0)
TUNING_GOAL_SEED = 100


def _progress_speed(steps: np.ndarray, duration: float, bearing: float) -> float:
    """Return the most progress per second toward ``bearing`` of (dx, dy, ...) rows."""
    u = np.array([math.cos(bearing), math.sin(bearing)])
    return float((steps[:, :2] @ u).max()) / duration


def bound(out) -> None:
    from hexapod_gait.trajectory import POSE_TRANSITION_S
    from hexapod_navigation.core.config import NavigationConfig
    from hexapod_navigation.core.loading import load_navigation
    from hexapod_navigation.core.repertoire import shipped_repertoire
    from hexapod_navigation.core.step_bank import shipped_step_bank
    from hexapod_navigation.core.tripod import TripodSteps
    from hexapod_navigation.offline.experiment import draw_goals

    data = load_navigation(shipped_repertoire(), shipped_step_bank())
    rep, bank = data.repertoire, data.bank
    allowed = rep.min_stance() >= NavigationConfig().min_stance_legs
    tolerance = NavigationConfig().tolerance
    period = TripodSteps().period
    cycles = bank.tripods()  # (1 + hypotheses, 8, 3): intact first
    lifted = [h for h, d in enumerate(bank.damages) if {x.kind for x in d.legs} == {'lifted'}]
    print('## 1. bound: the damage known, straight at the best speed toward the goal', file=out)
    print(
        f'steps: {int(allowed.sum())} repertoire gaits of {rep.step_duration:g} s, 8 tripod'
        f' cycles of {period:g} s; first transition {POSE_TRANSITION_S:g} s; tolerance'
        f' {tolerance:g} m; lifted cases: {len(lifted)}',
        file=out,
    )

    def times(goals, steps, tripod) -> list[float]:
        out_t = []
        for gx, gy in goals:
            bearing = math.atan2(gy, gx)
            v = max(
                _progress_speed(steps[allowed], rep.step_duration, bearing),
                _progress_speed(tripod, period, bearing),
            )
            out_t.append(POSE_TRANSITION_S + (math.hypot(gx, gy) - tolerance) / v)
        return out_t

    for seed in SEEDS:
        goals = draw_goals(10, seed)
        intact = float(
            np.median(times(goals, np.column_stack([rep.moves, 0 * rep.moves[:, 0]]), cycles[0]))
        )
        damaged = float(
            np.median(np.concatenate([times(goals, bank.steps[h], cycles[h + 1]) for h in lifted]))
        )
        print(
            f'goals of seed {seed}: intact {intact:.2f} s, lifted S1-S4 {damaged:.2f} s,'
            f' ratio {damaged / intact:.2f}',
            file=out,
        )


def known(out) -> None:
    from hexapod_navigation.core.config import NavigationConfig
    from hexapod_navigation.core.repertoire import shipped_repertoire
    from hexapod_navigation.core.step_bank import shipped_step_bank
    from hexapod_navigation.offline.experiment import NavigationSettings, run_navigation

    print('\n## 2. navigate on the tuning goals (seed 100), lifted legs', file=out)
    for name, config, reported in (
        ('defaults, damage not told', NavigationConfig(), False),
        (
            'damage told, prior_reported 0.999',
            replace(NavigationConfig(), prior_reported=0.999),
            True,
        ),
    ):
        settings = NavigationSettings(
            repertoire=shipped_repertoire(),
            goals=10,
            goal_seed=TUNING_GOAL_SEED,
            methods=('repertoire',),
            config=config,
            bank=shipped_step_bank(),
            reported=reported,
        )
        rows, _ = run_navigation(settings, 2)
        by = {}
        for r in rows:
            by.setdefault(r.scenario, []).append(r)
        cells = []
        for s, rs in sorted(by.items()):
            t = [r.walking_time for r in rs if r.reached]
            cells.append(f'{s} {100 * len(t) / len(rs):.0f} % {np.median(t):.2f} s')
        intact = np.median([r.walking_time for r in by['S0'] if r.reached])
        damaged = np.median([r.walking_time for r in rows if r.scenario != 'S0' and r.reached])
        print(
            f'{name}: '
            + ', '.join(cells)
            + f'; damaged {damaged:.2f} s, {damaged / intact:.2f} x intact',
            file=out,
            flush=True,
        )


def specialists(out) -> None:
    from hexapod_adapt.mapping.archive import load_archive
    from hexapod_adapt.mapping.maps import CEILINGS, shipped_map
    from hexapod_adapt.mapping.simulation import worker_simulator
    from hexapod_adapt.online.ceiling import cached_ceiling
    from hexapod_gait.parameters import from_genotype, from_omni_genotype, to_omni_genotype
    from hexapod_navigation.core.config import NavigationConfig
    from hexapod_navigation.core.loading import load_navigation
    from hexapod_navigation.core.repertoire import shipped_repertoire
    from hexapod_navigation.core.step_bank import shipped_step_bank
    from hexapod_sim.evaluation import evaluate_displacements

    data = load_navigation(shipped_repertoire(), shipped_step_bank())
    rep, bank = data.repertoire, data.bank
    allowed = rep.min_stance() >= NavigationConfig().min_stance_legs
    archive = load_archive(shipped_map())
    sim = worker_simulator(rep.engine)
    print(
        "\n## 3. the map's fastest gait under each lifted case, one step from rest"
        " [m/s], against the repertoire's best toward the same direction",
        file=out,
    )
    print('case | ceiling (5 s trial) | own crab angle: gait / repertoire | reverse', file=out)
    ratios = []
    for h, damage in enumerate(bank.damages):
        if {x.kind for x in damage.legs} != {'lifted'}:
            continue
        ceiling = cached_ceiling(archive, damage, rep.engine, [shipped_map(CEILINGS)])
        gait = from_genotype(archive.genotypes[ceiling.best_niche])
        cells = []
        for turn in (0.0, math.pi):
            angle = (gait.crab_angle + turn + math.pi) % (2 * math.pi) - math.pi
            genes = to_omni_genotype(replace(gait, crab_angle=angle))
            (m,) = evaluate_displacements(
                [genes],
                sim,
                rep.step_duration,
                collisions_fatal=False,
                failed_legs=damage,
                decode=from_omni_genotype,
            )
            if m.reason:
                cells.append('--')
                continue
            speed = math.hypot(m.x, m.y) / rep.step_duration
            best = _progress_speed(bank.steps[h][allowed], rep.step_duration, math.atan2(m.y, m.x))
            cells.append(f'{speed:.2f} / {best:.2f}')
            if turn == 0.0:
                ratios.append(speed / best)
        print(
            f'{damage.label} | {ceiling.best_speed:.2f} | {cells[0]} | {cells[1]}',
            file=out,
            flush=True,
        )
    print(
        f"own crab angle: the gait walks {np.median(ratios):.2f} x the repertoire's best"
        f' (median; {min(ratios):.2f}-{max(ratios):.2f})',
        file=out,
    )


def main(argv: list[str] | None = None) -> int:
    # no options: --help says what the study does instead of running it
    argparse.ArgumentParser(description=__doc__.strip().splitlines()[0]).parse_args(argv)
    out = sys.stdout
    bound(out)
    known(out)
    specialists(out)
    return 0


if __name__ == '__main__':
    sys.exit(main())
