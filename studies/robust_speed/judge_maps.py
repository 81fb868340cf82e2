# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Decide the robust-speed study (issue 66, deliverable 2): which candidate map walks best elsewhere.

Each candidate map's 300 fastest gaits (by its stored statistic) and 100 others at random (seed
0) are walked on PyBullet at its converged step, intact, 5 s, collisions not fatal
(:func:`hexapod_adapt.mapping.transfer.transfer_figures`). The decision rule is the one
studies/robust_speed/README.md wrote before the runs (:func:`decide`). ``--judge`` walks the
winner and the nominal map on DART as well, reported, deciding nothing. Each map's PyBullet
figures are kept in DIR/judged.json (by a hash of the map's gaits), so the maps finished so far
may be walked while the others run, and each is walked once.

    python -m studies.robust_speed.judge_maps --maps DIR [--judge]
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
from dataclasses import asdict, dataclass
import hashlib
import json
from pathlib import Path

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.transfer import transfer_figures, TransferFigures
from hexapod_sim import create_simulator, SimConfig
import numpy as np
from studies.robust_speed.candidates import CANDIDATES

#: Within this of a candidate with fewer variants, the one with fewer wins [m/s].
CHEAPER_MARGIN = 0.005


@dataclass(frozen=True)
class Judged:
    """One candidate map's figures on PyBullet."""

    name: str
    variants: int
    filled: int
    figures: TransferFigures


def decide(judged: list[Judged]) -> str:
    """
    Return the winner's name by the README's rule.

    The highest median PyBullet speed of the 100 fastest among the candidates that tip no more
    of them than the nominal map; then, of the candidates with fewer variants within
    :data:`CHEAPER_MARGIN` of it, the one with the fewest (ties: the faster).
    """
    nominal = next(j for j in judged if j.name == 'nominal')
    eligible = [j for j in judged if j.figures.top_tipped <= nominal.figures.top_tipped]
    best = max(eligible, key=lambda j: j.figures.top_speed_median)
    close = [
        j
        for j in eligible
        if j.variants < best.variants
        and j.figures.top_speed_median >= best.figures.top_speed_median - CHEAPER_MARGIN
    ]
    if close:
        best = min(close, key=lambda j: (j.variants, -j.figures.top_speed_median))
    return best.name


def _walk(path: Path) -> TransferFigures:
    """Return one map's figures on PyBullet at its converged step (a worker's task)."""
    with create_simulator(SimConfig.converged('pybullet')) as sim:
        return transfer_figures(load_archive(path), sim)


def _digest(path: Path) -> str:
    """Return a hash of a map's gaits and speeds (a file's bytes change when it is re-packed)."""
    archive = load_archive(path)
    h = hashlib.sha256()
    for array in (archive.centroids, archive.fitness, archive.descriptors, archive.genotypes):
        h.update(np.ascontiguousarray(array, dtype=np.float64).tobytes())
    return h.hexdigest()


def judge_finished(maps: Path, workers: int = 1) -> list[Judged]:
    """Return the figures of every finished candidate map, walking those not yet kept."""
    kept_path = maps / 'judged.json'
    kept = json.loads(kept_path.read_text()) if kept_path.is_file() else {}
    paths = {name: maps / f'{name}.npz' for name in CANDIDATES}
    digests = {n: _digest(p) for n, p in paths.items() if p.is_file()}
    todo = [n for n, d in digests.items() if kept.get(n, {}).get('sha256') != d]
    with cf.ProcessPoolExecutor(max(1, min(workers, len(todo) or 1))) as pool:
        futures = {pool.submit(_walk, paths[n]): n for n in todo}
        for future in cf.as_completed(futures):
            name = futures[future]
            kept[name] = {'sha256': digests[name], 'figures': asdict(future.result())}
            tmp = kept_path.with_suffix('.tmp')
            tmp.write_text(json.dumps(kept, indent=1))
            tmp.replace(kept_path)
    judged = []
    for name in digests:
        figures = TransferFigures(**kept[name]['figures'])
        filled = load_archive(paths[name]).n_filled
        judged.append(Judged(name, CANDIDATES[name][0], filled, figures))
        print(f'{name}: {figures}', flush=True)
    return judged


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--maps', type=Path, required=True, help='the finished maps, NAME.npz')
    parser.add_argument('--judge', action='store_true', help='also DART, winner and nominal')
    parser.add_argument('--workers', type=int, default=2, help='maps walked at once')
    args = parser.parse_args()
    judged = judge_finished(args.maps, args.workers)
    missing = [name for name in CANDIDATES if name not in {j.name for j in judged}]
    if missing:
        print(f'not finished: {", ".join(missing)}; nothing decided')
        return
    winner = decide(judged)
    print(
        '\n| candidate | gaits | its 100 fastest: stored median | PyBullet median | tipped '
        '| Spearman (400) |'
    )
    print('|---|---|---|---|---|---|')
    for j in judged:
        f = j.figures
        print(
            f'| {j.name}{" (winner)" if j.name == winner else ""} | {j.filled} '
            f'| {f.top_map_speed_median:.3f} m/s | {f.top_speed_median:.3f} m/s '
            f'| {f.top_tipped} | {f.spearman:.3f} |'
        )
    if args.judge:
        with create_simulator(SimConfig.converged('dart')) as sim:
            for name in dict.fromkeys(('nominal', winner)):
                f = transfer_figures(load_archive(args.maps / f'{name}.npz'), sim)
                print(
                    f'DART (judge), {name}: 100 fastest median {f.top_speed_median:.3f} m/s, '
                    f'{f.top_tipped} tipped, Spearman {f.spearman:.3f}'
                )


if __name__ == '__main__':
    main()
