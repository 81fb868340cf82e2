# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Keep the robust-speed study's progress in the repository, small enough to commit.

A machine may be new next session (2026-12-04: the study's 7 checkpoints, about 3 core-hours,
were lost with one). Each candidate's checkpoint (or finished map) and log are kept in
``studies/robust_speed/progress``: the same arrays compressed, without the centroids (the default
map's, put back on restore and checked against the file's centroid hash), so a sparse map's
3.6 MB file keeps in a few hundred kB. A file is replaced only by one further on.

    python -m studies.robust_speed.progress save --tree ../robust-study     # before a session ends
    python -m studies.robust_speed.progress restore --tree ../robust-study  # robust_study.sh does
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
import shutil

from hexapod_adapt.mapping.archive import centroid_hash, load_archive
from hexapod_util.files import copy_whole_rows
from hexapod_util.npz import write_npz
import numpy as np

KEEP = Path(__file__).resolve().parent / 'progress'
RUNS = 'tuning/robust_speed'  # the runs' folder inside the study's worktree
DEFAULT_MAP = 'hexapod_adapt/maps/default_map.npz'


def _evaluations(path: Path) -> int:
    """Return the evaluations a map or checkpoint holds (-1 if missing)."""
    if not path.is_file():
        return -1
    with np.load(path, allow_pickle=False) as data:
        return int(json.loads(str(data['metadata'])).get('evaluations', 0))


def _repack(src: Path, dest: Path, centroids: np.ndarray | None) -> None:
    """Write src's arrays to dest atomically: compressed, without or with the given centroids."""
    with np.load(src, allow_pickle=False) as data:
        arrays = {k: data[k] for k in data.files if k != 'centroids'}
    if centroids is not None:
        meta = json.loads(str(arrays['metadata']))
        if meta.get('centroid_hash') != centroid_hash(centroids):
            raise ValueError(f'{src}: its niches are not the default map (centroid hash)')
        arrays = {'centroids': centroids, **arrays}
    write_npz(dest, arrays, compressed=centroids is None)


def save(tree: Path, keep: Path = KEEP) -> list[str]:
    """Copy the worktree's checkpoints and finished maps into ``keep``; return what was saved."""
    keep.mkdir(parents=True, exist_ok=True)
    saved = []
    for log in sorted((tree / RUNS).glob('*.npz.log.jsonl')):
        name = log.name[: -len('.log.jsonl')]
        for suffix in ('', '.ckpt.npz'):  # the finished map first: then its checkpoint is stale
            src = tree / RUNS / (name + suffix)
            if not src.is_file():
                continue
            finished = suffix == ''
            kept_map = _evaluations(keep / name)
            if not finished and kept_map >= 0:
                break  # the map is kept finished already
            here, kept = _evaluations(src), max(_evaluations(keep / (name + suffix)), kept_map)
            if here <= kept:
                if here < kept:
                    print(f'not saved: {keep} holds {name} further on than {tree}')
                break  # (as far on: kept already)
            _repack(src, keep / (name + suffix), None)
            copy_whole_rows(log, keep / log.name)
            if finished:
                (keep / (name + '.ckpt.npz')).unlink(missing_ok=True)
            saved.append(f'{name + suffix} ({here} evaluations)')
            break
    judged = tree / RUNS / 'judged.json'
    if judged.is_file():
        shutil.copyfile(judged, keep / 'judged.json')
    return saved


def restore(tree: Path, keep: Path = KEEP) -> list[str]:
    """Put the kept progress into the worktree where it is further on; return what was."""
    runs = tree / RUNS
    runs.mkdir(parents=True, exist_ok=True)
    centroids = load_archive(tree / DEFAULT_MAP).centroids
    restored = []
    for kept in sorted(keep.glob('*.npz')):  # finished maps and checkpoints
        dest = runs / kept.name
        name = kept.name.removesuffix('.ckpt.npz')
        if max(_evaluations(dest), _evaluations(runs / name)) >= _evaluations(kept):
            continue
        _repack(kept, dest, centroids)
        log = keep / f'{name}.log.jsonl'
        if log.is_file():
            shutil.copyfile(log, runs / log.name)
        restored.append(f'{kept.name} ({_evaluations(kept)} evaluations)')
    if (keep / 'judged.json').is_file() and not (runs / 'judged.json').is_file():
        shutil.copyfile(keep / 'judged.json', runs / 'judged.json')
    return restored


def main(argv: list[str] | None = None) -> None:
    """Save or restore the study's progress."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[1])
    parser.add_argument('action', choices=('save', 'restore'))
    parser.add_argument('--tree', type=Path, default=Path('../robust-study'))
    args = parser.parse_args(argv)
    done = (save if args.action == 'save' else restore)(args.tree)
    print(f'{args.action}d: ' + (', '.join(done) if done else 'nothing'))


if __name__ == '__main__':
    main()
