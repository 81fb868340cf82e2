# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The transfer study's report (studies/transfer/README.md): candidates on PyBullet, the winner.

For every candidate map that is finished: its cost in CPU core-hours (its generation log), and
its transfer figures on PyBullet (``hexapod_adapt.mapping.transfer``). The rule fixed before the
runs then picks the winner. ``--judge`` measures the winner on the judge (DART) too: once, for
the report.

    python -m studies.transfer.report [--judge]
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.plots import log_runs
from hexapod_adapt.mapping.transfer import transfer_figures, TransferFigures
from hexapod_sim import create_simulator, SimConfig
from hexapod_sim.simulator import JUDGE_ENGINE

BUDGET = 200_000
CANDIDATES = {
    'A1 cma_mae': Path('studies/out/map_study/cma_mae_10000_s1.npz'),
    'A2 iso_line': Path('studies/out/map_study/iso_line_10000_s1.npz'),
    'B1 cma_mae + walk guards': Path('studies/out/transfer_study/walk_cma_mae_10000_s1.npz'),
    'B2 iso_line + walk guards': Path('studies/out/transfer_study/walk_iso_line_10000_s1.npz'),
}
#: The rule (studies/transfer/README.md): out above this many top-100 tip-overs on PyBullet ...
MAX_TIPPED = 10
#: ... then the highest Spearman; within this of each other, the higher top-100 speed median.
SPEARMAN_TIE = 0.05


@dataclass(frozen=True)
class Candidate:
    """One finished candidate map and its figures on PyBullet."""

    name: str
    path: Path
    core_hours: float | None  # CPU core-hours (None: its log predates the CPU time)
    held_hours: float  # core-hours held: wall time x workers
    filled: int
    pybullet: TransferFigures


def choose(candidates: list[Candidate]) -> Candidate:
    """Apply the study's rule to the candidates' PyBullet figures."""
    kept = [c for c in candidates if c.pybullet.top_tipped <= MAX_TIPPED]
    if not kept:
        return min(candidates, key=lambda c: c.pybullet.top_tipped)
    best = max(c.pybullet.spearman for c in kept)
    close = [c for c in kept if c.pybullet.spearman >= best - SPEARMAN_TIE]
    return max(close, key=lambda c: c.pybullet.top_speed_median)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--judge', action='store_true', help='measure the winner on the judge')
    args = parser.parse_args()
    found = []
    with create_simulator(SimConfig(engine='pybullet')) as sim:
        for name, path in CANDIDATES.items():
            if not path.is_file():
                print(f'{name}: not finished ({path} missing)')
                continue
            archive = load_archive(path)
            if archive.metadata.get('evaluations', 0) < BUDGET:
                print(f'{name}: {archive.metadata.get("evaluations")} of {BUDGET} evaluations')
                continue
            runs = log_runs(path.with_name(path.name + '.log.jsonl'))
            known = all(r.cpu_s is not None for r in runs)
            cpu = sum(r.cpu_s for r in runs) / 3600 if known else None
            held = sum(r.core_seconds for r in runs) / 3600
            figures = transfer_figures(archive, sim)
            found.append(Candidate(name, path, cpu, held, archive.n_filled, figures))
    print(
        '| candidate | CPU core-hours | core-hours held | niches | PyBullet top-100 median'
        ' | tipped | Spearman |'
    )
    print('|---|---|---|---|---|---|---|')
    for c in found:
        f = c.pybullet
        cpu = f'{c.core_hours:.2f}' if c.core_hours is not None else 'not logged'
        print(
            f'| {c.name} | {cpu} | {c.held_hours:.2f} | {c.filled} | {f.top_speed_median:.3f}'
            f' m/s | {f.top_tipped} | {f.spearman:.3f} |'
        )
    if len(found) < len(CANDIDATES):
        print('not every candidate is finished: no winner yet')
        return
    winner = choose(found)
    print(f'winner by the rule: {winner.name}')
    if args.judge:
        with create_simulator(SimConfig(engine=JUDGE_ENGINE)) as judge:
            f = transfer_figures(load_archive(winner.path), judge)
        print(
            f'the judge ({JUDGE_ENGINE}), once: top-100 median {f.top_speed_median:.3f} m/s,'
            f' {f.top_tipped} tipped, Spearman {f.spearman:.3f}'
        )


if __name__ == '__main__':
    main()
