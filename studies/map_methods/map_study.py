# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Which emitter set and niche count make the best map for the budget (issue 30's study).

Every run is a ``generate_map`` of STUDY_EVALUATIONS MuJoCo evaluations, with the presets
first, resumable (``--resume``; run this program again after an interruption). The maps go to
``studies/out/map_study/`` (not committed: megabytes each; their logs are).

The decision rule, fixed before any run (studies/map_methods/README.md):

1. **Screen** the emitter sets at 10,000 niches, seed 1: iso_line (today's), cma_me, cma_mae,
   bandit.
2. **Niche counts**: the screen's winner at 5,000 and 20,000 niches, seed 1.
3. **Confirm** the two best configurations of 1-2 with seed 2; the winner is the better of the
   two by the mean of their seed-1 and seed-2 scores.

A configuration's **score** is the median, over STUDY_DAMAGES (tuning damage: legs locked, weak
or with a lost tibia; never S1-S4's lifted legs), of the map's ceiling under that damage: the
best speed any of its gaits walks with it (MuJoCo, collisions not fatal). A configuration whose
QD-score per niche is below 90 % of iso_line's at 10,000 niches is out: a map is for a search,
and a thin one has little to offer M-BOA. Ties within 0.005 m/s go to the higher QD-score per
niche.

    python -m studies.map_methods.map_study run     # the runs the rule calls for next (resumable)
    python -m studies.map_methods.map_study report  # the table (results/map_study.txt), what next
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
import os
from pathlib import Path
import statistics
import subprocess
import sys

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.online.ceiling import ceiling
from hexapod_sim.damage import Damage
from hexapod_sim.scenarios import scenario
from hexapod_util.cli import run_command
from hexapod_util.files import atomic_write_bytes

WS = Path(__file__).resolve().parent.parent
OUT = WS / 'studies' / 'out' / 'map_study'
REPORT = WS / 'docs' / 'studies' / 'map_study.txt'
STUDY_EVALUATIONS = 200_000
#: Tuning damage, one orientation of S1, S3 and S4 each, three kinds: 9 cases.
STUDY_DAMAGES = tuple(
    Damage.of(kind, scenario(name)[0])
    for kind in ('locked', 'weak', 'no_tibia')
    for name in ('S1', 'S3', 'S4')
)
SCREEN = ('iso_line', 'cma_me', 'cma_mae', 'bandit')


@dataclass(frozen=True)
class Run:
    """One map of the study."""

    emitters: str
    niches: int
    seed: int

    @property
    def name(self) -> str:
        """Return the run's file stem."""
        return f'{self.emitters}_{self.niches}_s{self.seed}'

    @property
    def path(self) -> Path:
        """Return the run's map."""
        return OUT / f'{self.name}.npz'


@dataclass(frozen=True)
class Score:
    """What the rule looks at."""

    run: Run
    evaluations: int
    filled: int
    qd_per_niche: float  # QD-score / niches [m]
    mean_elite: float  # m/s
    best: float  # m/s
    ceilings: tuple[float, ...]  # m/s, one per STUDY_DAMAGES case

    @property
    def score(self) -> float:
        """Return the median ceiling [m/s]."""
        return statistics.median(self.ceilings)


def generate(run: Run, workers: int) -> None:
    """Make (or continue) one run's map."""
    command = [
        sys.executable, '-m', 'hexapod_adapt.mapping.generate_map_cli',
        '--out', str(run.path), '--engine', 'mujoco', '--niches', str(run.niches),
        '--evaluations', str(STUDY_EVALUATIONS), '--seed', str(run.seed), '--with-presets',
        '--emitters', run.emitters, '--cvt-dir', str(OUT), '--workers', str(workers),
        '--checkpoint-every', '120', '--log-every', '30', '--no-bar', '--resume',
    ]  # fmt: skip
    print(f'{run.name}: {" ".join(command[2:])}', flush=True)
    subprocess.run(command, check=True)


def finished(run: Run) -> bool:
    """Whether the run's map holds its whole budget."""
    if not run.path.is_file():
        return False
    return load_archive(run.path).metadata.get('evaluations', 0) >= STUDY_EVALUATIONS


def measure(run: Run, workers: int) -> Score:
    """Score a finished map (its ceilings are cached in studies/out/map_study/ceilings)."""
    archive = load_archive(run.path)
    speeds = archive.speeds()[archive.elite_indices()]
    stats = archive.stats()
    ceilings = tuple(
        ceiling(archive, d, 'mujoco', OUT / 'ceilings', workers).best_speed for d in STUDY_DAMAGES
    )
    return Score(
        run,
        archive.metadata['evaluations'],
        archive.n_filled,
        stats.qd_score / archive.n_niches,
        float(speeds.mean()),
        float(speeds.max()),
        ceilings,
    )


def best(scores: list[Score], floor: float) -> list[Score]:
    """Return the scores the rule keeps (QD-score per niche >= floor), best first."""
    kept = [s for s in scores if s.qd_per_niche >= floor]
    return sorted(kept, key=lambda s: (round(-s.score / 0.005), -s.qd_per_niche))


def plan(scores: dict[str, Score]) -> tuple[list[Run], str]:
    """Return the runs the rule calls for next (given what is scored), and where it stands."""
    screen = [Run(e, 10_000, 1) for e in SCREEN]
    missing = [r for r in screen if r.name not in scores]
    if missing:
        return missing, 'stage 1: screening the emitter sets at 10,000 niches'
    floor = 0.9 * scores[Run('iso_line', 10_000, 1).name].qd_per_niche
    winner = best([scores[r.name] for r in screen], floor)[0].run
    counts = [Run(winner.emitters, n, 1) for n in (5_000, 20_000)]
    missing = [r for r in counts if r.name not in scores]
    if missing:
        return missing, f'stage 2: niche counts with {winner.emitters}'
    seed1 = best([scores[r.name] for r in screen + counts], floor)[:2]
    confirm = [Run(s.run.emitters, s.run.niches, 2) for s in seed1]
    missing = [r for r in confirm if r.name not in scores]
    if missing:
        return missing, 'stage 3: confirming the two best with seed 2'

    def mean(s: Score) -> float:
        return (s.score + scores[Run(s.run.emitters, s.run.niches, 2).name].score) / 2

    chosen = max(seed1, key=mean).run
    return [], f'done: {chosen.emitters} at {chosen.niches} niches'


def table(scores: dict[str, Score], status: str) -> str:
    """Return the study's table as text."""
    head = (
        f'{"run":26s} {"evals":>8s} {"filled":>7s} {"QD/niche":>9s} {"mean":>6s} {"best":>6s}'
        f' {"score":>6s}  ceilings (m/s): ' + ' | '.join(d.label for d in STUDY_DAMAGES)
    )
    lines = [head]
    for s in scores.values():
        lines.append(
            f'{s.run.name:26s} {s.evaluations:8d} {s.filled:7d} {s.qd_per_niche:9.3f}'
            f' {s.mean_elite:6.3f} {s.best:6.3f} {s.score:6.3f}  '
            + ' '.join(f'{c:.3f}' for c in s.ceilings)
        )
    return '\n'.join(lines + ['', status]) + '\n'


def main(argv: list[str] | None = None) -> int:
    """Run or report the study."""
    ap = argparse.ArgumentParser(prog='map_study', description=__doc__.split('\n\n')[0])
    ap.add_argument('what', choices=('run', 'report'))
    ap.add_argument('--workers', type=int, default=int(os.environ.get('WORKERS', '2')))
    args = ap.parse_args(argv)

    def body() -> int:
        OUT.mkdir(parents=True, exist_ok=True)
        while True:
            scores: dict[str, Score] = {}
            for path in sorted(OUT.glob('*_s[0-9]*.npz')):
                if path.name.endswith('.ckpt.npz'):
                    continue
                emitters, niches, seed = path.stem.rsplit('_', 2)
                run = Run(emitters, int(niches), int(seed[1:]))
                if finished(run):
                    scores[run.name] = measure(run, args.workers)
            runs, status = plan(scores)
            text = table(scores, status)
            atomic_write_bytes(REPORT, text.encode())
            print(text, flush=True)
            if args.what == 'report' or not runs:
                return 0
            generate(runs[0], args.workers)

    return run_command('map_study', body, 'each map resumes from its checkpoint: run it again')


if __name__ == '__main__':
    sys.exit(main())
