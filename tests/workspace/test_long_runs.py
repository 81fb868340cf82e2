# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""save_progress.sh keeps a running map's progress where git can keep it, and never goes back."""

from __future__ import annotations

import json
import os
from pathlib import Path
import re
import shutil
import subprocess
import sys
import time

from hexapod_adapt.mapping.archive import load_archive
import numpy as np
import pytest

WS = Path(__file__).resolve().parents[2]
SAVE = WS / 'scripts' / 'save_progress.sh'
DEMO_MAP = WS / 'hexapod_adapt' / 'maps' / 'demo_map.npz'
MAKE_DEFAULT_MAP = WS / 'hexapod_adapt' / 'maps' / 'make_default_map.sh'


def _made_by(archive, emitters: str) -> None:
    """Record ``emitters`` in a map's metadata as generate_map does (iso_line: left out)."""
    from hexapod_adapt.mapping.map_elites import MapElitesConfig

    identity = MapElitesConfig(evaluations=1, emitters=emitters).identity()
    archive.metadata['map_elites'].pop('emitters', None)
    if 'emitters' in identity:
        archive.metadata['map_elites']['emitters'] = identity['emitters']


def _start_map(tree: Path) -> subprocess.Popen:
    """A small map in the layout of resume_default_map.sh's worktree, checkpointing often."""
    maps = tree / 'hexapod_adapt' / 'maps'
    maps.mkdir(parents=True)
    (tree / 'out').mkdir()
    proc = subprocess.Popen(
        [sys.executable, '-m', 'hexapod_adapt.mapping.generate_map_cli',
         '--out', str(maps / 'default_map.npz'), '--niches', '30', '--cvt-samples', '3000',
         '--evaluations', '10000000', '--seed', '1', '--workers', '1',
         '--checkpoint-every', '2', '--log-every', '1', '--quiet'],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )  # fmt: skip
    (tree / 'out' / 'default_map.pid').write_text(f'{proc.pid}\n')
    ckpt = maps / 'default_map.npz.ckpt.npz'
    deadline = time.monotonic() + 120
    while not ckpt.exists():
        assert proc.poll() is None, 'the map stopped before its first checkpoint'
        assert time.monotonic() < deadline, 'no checkpoint within 120 s'
        time.sleep(0.2)
    return proc


def _save(tree: Path, keep: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        ['bash', str(SAVE), str(tree), str(tree.parent / 'no_ceilings'), str(keep)],
        capture_output=True, text=True, timeout=120,
        env={
            **os.environ,
            'TRANSFER_TREE': str(tree.parent / 'no_transfer_study'),
        },
    )  # fmt: skip


@pytest.mark.slow
def test_a_running_map_is_stopped_at_a_checkpoint_and_its_progress_kept(tmp_path):
    tree, keep = tmp_path / 'mapgen', tmp_path / 'kept'
    proc = _start_map(tree)
    try:
        r = _save(tree, keep)
        assert r.returncode == 0, r.stderr
        assert proc.wait(timeout=30) is not None  # stopped, not left running
    finally:
        if proc.poll() is None:
            proc.kill()
    maps = tree / 'hexapod_adapt' / 'maps'
    kept = load_archive(keep / 'default_map.npz.ckpt.npz').metadata['evaluations']
    assert kept > 0
    # the very checkpoint the run ended on (nothing written after the copy)
    assert kept == load_archive(maps / 'default_map.npz.ckpt.npz').metadata['evaluations']
    assert f'{kept} evaluations' in r.stdout
    text = (keep / 'default_map.npz.log.jsonl').read_text()
    assert text.endswith('\n')  # whole rows only
    rows = [json.loads(line) for line in text.splitlines()]
    assert rows and rows[-1]['evaluations'] > 0


@pytest.mark.slow
def test_a_checkpoint_further_on_is_never_replaced(tmp_path):
    tree, keep = tmp_path / 'mapgen', tmp_path / 'kept'
    keep.mkdir()
    further = keep / 'default_map.npz.ckpt.npz'
    shutil.copy(DEMO_MAP, further)  # 25,000 evaluations: more than the small run gets to
    before = further.read_bytes()
    proc = _start_map(tree)
    try:
        r = _save(tree, keep)
    finally:
        proc.kill()
    assert r.returncode == 1
    assert 'further on (25000 evaluations)' in r.stderr
    assert further.read_bytes() == before


@pytest.mark.slow
def test_a_shipped_map_is_told_from_one_in_the_making(tmp_path):
    """
    resume_long_runs.sh restarts no map once the shipped one is make_default_map.sh's.

    Its evaluations, and its emitters when the script names them.
    """
    maps = tmp_path / 'hexapod_adapt' / 'maps'
    maps.mkdir(parents=True)
    helper = WS / 'scripts' / 'map_progress.sh'
    archive = load_archive(DEMO_MAP)
    _made_by(archive, 'iso_line')  # which leaves it out of the metadata (seen 2026-11-28)
    archive.save(maps / 'default_map.npz')
    for asked, emitters, shipped in (
        (25000, '', 'yes'),
        (25001, '', 'no'),
        (25000, ' --emitters iso_line', 'yes'),
        (25000, ' --emitters cma_mae', 'no'),  # a map made by another method
    ):
        script = f'generate_map --evaluations {asked} --seed 1{emitters}\n'
        (maps / 'make_default_map.sh').write_text(script)
        r = subprocess.run(
            ['bash', '-c', f'source {helper} && default_map_shipped'],
            cwd=tmp_path, capture_output=True, text=True, timeout=60,
        )  # fmt: skip
        assert r.stdout.strip() == shipped, (asked, r.stdout, r.stderr)


def test_no_ceilings_start_after_a_map_run_that_wrote_nothing(tmp_path):
    then = WS / 'hexapod_adapt' / 'maps' / 'then_ceilings.sh'
    tree = tmp_path / 'mapgen'
    (tree / 'out').mkdir(parents=True)
    r = subprocess.run(['bash', str(then), str(tree)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0 and 'no map run' in r.stdout
    ended = subprocess.Popen(['true'])
    ended.wait()
    (tree / 'out' / 'default_map.pid').write_text(f'{ended.pid}\n')
    r = subprocess.run(['bash', str(then), str(tree)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0 and 'ended without writing' in r.stdout
    assert 'starting its ceilings' not in r.stdout


@pytest.mark.slow
def test_a_written_map_is_kept_to_ship_with_its_ceilings(tmp_path):
    """The finished map is in the repository before its ceilings, which take sessions, are."""
    tree, keep = tmp_path / 'mapgen', tmp_path / 'kept'
    maps = tree / 'hexapod_adapt' / 'maps'
    maps.mkdir(parents=True)
    target = int(re.search(r'--evaluations (\d+)', MAKE_DEFAULT_MAP.read_text()).group(1))
    emitters = re.search(r'--emitters (\w+)', MAKE_DEFAULT_MAP.read_text()).group(1)
    archive = load_archive(DEMO_MAP)
    archive.metadata['evaluations'] = target  # as the finished default map says
    _made_by(archive, emitters)
    archive.save(maps / 'default_map.npz')
    (maps / 'default_map.npz.log.jsonl').write_text('{"evaluations": 1}\n')
    keep.mkdir()
    (keep / 'default_map.npz.ckpt.npz').write_bytes(b'the checkpoint it resumed from')
    r = _save(tree, keep)
    assert r.returncode == 0 and 'saved the finished map' in r.stdout, r.stdout + r.stderr
    assert load_archive(keep / 'default_map.npz').metadata['evaluations'] == target
    assert (keep / 'default_map.npz.log.jsonl').read_text() == '{"evaluations": 1}\n'
    assert not (keep / 'default_map.npz.ckpt.npz').exists()  # superseded by the map


@pytest.mark.slow
def test_the_shipped_map_is_not_copied_back(tmp_path):
    """Once shipped, the map run's written map is the repository's own: nothing to keep."""
    shipped = WS / 'hexapod_adapt' / 'maps' / 'default_map.npz'
    tree, keep = tmp_path / 'mapgen', tmp_path / 'kept'
    maps = tree / 'hexapod_adapt' / 'maps'
    maps.mkdir(parents=True)
    shutil.copy(shipped, maps / 'default_map.npz')
    helper = WS / 'scripts' / 'map_progress.sh'
    finished = subprocess.run(
        ['bash', '-c', f'source {helper} && default_map_shipped'],
        cwd=WS, capture_output=True, text=True, timeout=60,
    ).stdout.strip()  # fmt: skip
    r = _save(tree, keep)
    assert r.returncode == 0, r.stdout + r.stderr
    if finished == 'yes':  # the finished map ships: the run's copy is the repository's own
        assert 'nothing to save' in r.stdout, r.stdout
    # (while a new default map is made, the old shipped one in a worktree is not a finished map)
    assert not (keep / 'default_map.npz').exists()


def test_only_the_ceilings_computed_in_the_worktree_are_kept(tmp_path):
    """The worktree's checkout holds an older map's shipped cases: those are not kept."""
    tree, keep = tmp_path / 'ceilgen', tmp_path / 'kept'
    cache = tree / 'hexapod_adapt' / 'maps' / 'ceilings'
    cache.mkdir(parents=True)
    (cache / 'ceiling_mujoco_legs1_older.npz').write_bytes(b'checked out')
    subprocess.run(['git', 'init', '-q', str(tree)], check=True)
    subprocess.run(['git', '-C', str(tree), 'add', '.'], check=True)
    (cache / 'ceiling_mujoco_legs1_5unpowered-coxa_new.npz').write_bytes(b'computed')
    # the case in progress is kept; the one kept last time has finished since: it goes
    (cache / 'walking_ceiling_mujoco_legs2_now.npz').write_bytes(b'walked so far')
    (keep / 'ceilings').mkdir(parents=True)
    (keep / 'ceilings' / 'walking_ceiling_mujoco_legs1_5unpowered-coxa_new.npz').write_bytes(b'')
    r = subprocess.run(
        ['bash', str(SAVE), str(tmp_path / 'no_map'), str(tree), str(keep)],
        capture_output=True, text=True, timeout=60,
        env={
            **os.environ,
            'TRANSFER_TREE': str(tmp_path / 'no_transfer_study'),
        },
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in (keep / 'ceilings').iterdir()) == [
        'ceiling_mujoco_legs1_5unpowered-coxa_new.npz',
        'walking_ceiling_mujoco_legs2_now.npz',
    ]
    assert (keep / 'ceilings' / 'walking_ceiling_mujoco_legs2_now.npz').read_bytes() == (
        b'walked so far'
    )
    assert 'saved 1 ceiling cases' in r.stdout and 'saved the case in progress' in r.stdout


@pytest.mark.slow
def test_the_shipped_maps_new_ceilings_are_packed_into_its_cache(tmp_path):
    """After a map ships, its cases still being made join the shipped cache as they finish."""
    from hexapod_adapt.online.ceiling import cached_ceiling, ceiling, pack_ceilings

    shipped, tree = tmp_path / 'repo_maps', tmp_path / 'ceilgen'
    cache = tree / 'hexapod_adapt' / 'maps' / 'ceilings'
    (shipped / 'ceilings').mkdir(parents=True)
    cache.mkdir(parents=True)
    subprocess.run(['git', 'init', '-q', str(tree)], check=True)
    archive = load_archive(DEMO_MAP)
    keep = archive.elite_indices()[:4]
    archive.fitness[archive.elite_indices()[4:]] = float('nan')  # 4 gaits: a quick ceiling
    archive.save(shipped / 'default_map.npz')
    shutil.copy(shipped / 'default_map.npz', tree / 'hexapod_adapt' / 'maps' / 'default_map.npz')
    archive = load_archive(shipped / 'default_map.npz')
    assert len(archive.elite_indices()) == len(keep)
    ceiling(archive, [1], 'mujoco', cache_dir=cache)  # shipped already (packed below)
    shutil.copy(next(cache.glob('*.npz')), shipped / 'ceilings')
    pack_ceilings(shipped / 'ceilings')
    ceiling(archive, [2], 'mujoco', cache_dir=cache)  # finished since
    readme = shipped / 'ceilings' / 'README.md'
    readme.write_text('<!-- ceilings-summary: start -->\n<!-- ceilings-summary: end -->\n')
    r = subprocess.run(
        ['bash', str(SAVE), str(tmp_path / 'no_map'), str(tree), str(tmp_path / 'kept')],
        capture_output=True, text=True, timeout=120,
        env={
            **os.environ,
            'SHIPPED_MAPS': str(shipped),
            'TRANSFER_TREE': str(tmp_path / 'no_transfer_study'),
        },
    )  # fmt: skip
    assert r.returncode == 0, r.stdout + r.stderr
    assert f'saved 1 ceiling cases to {shipped / "ceilings"}' in r.stdout
    assert sorted(p.name for p in (shipped / 'ceilings').iterdir()) == [
        'README.md',
        'ceilings_mujoco_lifted_0.zip',
        'ceilings_mujoco_lifted_1.zip',
    ]
    for legs in ([1], [2]):
        assert cached_ceiling(archive, legs, 'mujoco', [shipped / 'ceilings']) is not None
    # the README's table counts both
    assert '| lifted | 2 of 21 (2) |' in readme.read_text()
    assert not (tmp_path / 'kept' / 'ceilings').exists()


def _transfer_save(tmp_path: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        ['bash', str(SAVE), str(tmp_path / 'no_map'), str(tmp_path / 'no_ceilings'),
         str(tmp_path / 'kept')],
        capture_output=True, text=True, timeout=60,
        env={
            **os.environ,
            'TRANSFER_TREE': str(tmp_path / 'transfer'),
            'TRANSFER_KEEP': str(tmp_path / 'checkpoints'),
            'TRANSFER_DONE': str(tmp_path / 'done'),
        },
    )  # fmt: skip


def _with_evaluations(path: Path, evaluations: int) -> None:
    """Write the demo map to ``path`` as if it held ``evaluations`` evaluations."""
    archive = load_archive(DEMO_MAP)
    archive.metadata['evaluations'] = evaluations
    archive.save(path)


@pytest.mark.slow
def test_the_transfer_study_keeps_checkpoints_further_on_and_finished_maps(tmp_path):
    """Run a: a checkpoint behind the kept one; run b: one further on; run c: finished."""
    runs = tmp_path / 'transfer' / 'tuning' / 'transfer_study'
    keep, done = tmp_path / 'checkpoints', tmp_path / 'done'
    runs.mkdir(parents=True)
    keep.mkdir()
    for name in ('walk_a', 'walk_b', 'walk_c'):
        (runs / f'{name}.npz.log.jsonl').write_text('{"evaluations": 5}\n{"evalu')  # torn row
    _with_evaluations(runs / 'walk_a.npz.ckpt.npz', 100)
    _with_evaluations(keep / 'walk_a.npz.ckpt.npz', 200)
    _with_evaluations(runs / 'walk_b.npz.ckpt.npz', 300)
    _with_evaluations(keep / 'walk_b.npz.ckpt.npz', 200)
    _with_evaluations(runs / 'walk_c.npz', 400)
    _with_evaluations(keep / 'walk_c.npz.ckpt.npz', 350)
    before_a = (keep / 'walk_a.npz.ckpt.npz').read_bytes()
    r = _transfer_save(tmp_path)
    assert r.returncode == 0, r.stderr
    assert 'walk_a.npz further on (200 evaluations)' in r.stderr
    assert (keep / 'walk_a.npz.ckpt.npz').read_bytes() == before_a
    assert not (keep / 'walk_a.npz.log.jsonl').exists()
    assert load_archive(keep / 'walk_b.npz.ckpt.npz').metadata['evaluations'] == 300
    assert (keep / 'walk_b.npz.log.jsonl').read_text() == '{"evaluations": 5}\n'
    assert load_archive(done / 'walk_c.npz').metadata['evaluations'] == 400
    assert (done / 'walk_c.npz.log.jsonl').read_text() == '{"evaluations": 5}\n'
    assert not (keep / 'walk_c.npz.ckpt.npz').exists()  # the run ended: its checkpoint goes


@pytest.mark.slow
def test_make_ceilings_counts_the_cases_the_shipped_cache_lacks():
    """resume_long_runs.sh starts no ceilings once this count is 0 (every case shipped)."""
    r = subprocess.run(
        ['bash', str(WS / 'hexapod_adapt' / 'maps' / 'make_ceilings.sh'), '--missing'],
        cwd=WS, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    # 8 kinds x 21 S1-S4 cases, the lifted ones shipped with the map, and the 3 check cases
    # (made in full beside their partial ones)
    assert 0 <= int(r.stdout) <= 8 * 21 - 21 + 3


def test_a_map_is_not_shipped_before_its_lifted_leg_ceilings(tmp_path):
    """ship_map.sh refuses, changing nothing, while a lifted-leg case is missing."""
    keep = tmp_path / 'in_progress'
    (keep / 'ceilings').mkdir(parents=True)
    shutil.copy(DEMO_MAP, keep / 'default_map.npz')
    (keep / 'default_map.npz.log.jsonl').write_text('{"evaluations": 1}\n')
    shipped = WS / 'hexapod_adapt' / 'maps' / 'default_map.npz'
    before = shipped.read_bytes(), (WS / 'hexapod_adapt' / 'config' / 'adapt.yaml').read_text()
    r = subprocess.run(
        ['bash', str(WS / 'hexapod_adapt' / 'maps' / 'ship_map.sh'), str(keep)],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert r.returncode == 1, r.stdout + r.stderr
    assert f'21 lifted-leg ceiling cases of {keep / "default_map.npz"} are not in' in r.stderr
    after = shipped.read_bytes(), (WS / 'hexapod_adapt' / 'config' / 'adapt.yaml').read_text()
    assert after == before and (keep / 'default_map.npz').exists()
    r = subprocess.run(
        ['bash', str(WS / 'hexapod_adapt' / 'maps' / 'ship_map.sh'), str(tmp_path / 'none')],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert r.returncode == 1 and 'no finished map with its log' in r.stderr


def _checkpoint(path: Path, evaluations: int) -> None:
    """Write the demo map to ``path`` as a checkpoint holding ``evaluations`` evaluations."""
    archive = load_archive(DEMO_MAP)
    archive.metadata['evaluations'] = evaluations
    pending = {'pending_index': np.arange(3), 'pending_genes': np.full((3, 32), 0.25)}
    archive.save(path, pending)


@pytest.mark.slow
def test_the_robust_study_keeps_small_checkpoints_and_restores_them_exactly(tmp_path):
    """Saved compressed without centroids, only when further on; restored to the same arrays."""
    from hexapod_adapt.mapping.map_elites import load_checkpoint
    from studies.robust_speed import progress

    tree, keep = tmp_path / 'robust-study', tmp_path / 'kept'
    runs = tree / progress.RUNS
    runs.mkdir(parents=True)
    keep.mkdir()
    (tree / 'hexapod_adapt' / 'maps').mkdir(parents=True)
    shutil.copyfile(DEMO_MAP, tree / progress.DEFAULT_MAP)
    for name in ('a', 'b', 'c'):
        (runs / f'{name}.npz.log.jsonl').write_text('{"evaluations": 5}\n{"evalu')  # torn row
    _checkpoint(runs / 'a.npz.ckpt.npz', 300)  # further on than the kept one
    _checkpoint(keep / 'a.npz.ckpt.npz', 200)
    _with_evaluations(runs / 'b.npz', 400)  # finished
    _checkpoint(keep / 'b.npz.ckpt.npz', 350)
    _checkpoint(runs / 'c.npz.ckpt.npz', 100)  # behind the kept one
    _checkpoint(keep / 'c.npz.ckpt.npz', 200)
    kept_c = (keep / 'c.npz.ckpt.npz').read_bytes()
    saved = progress.save(tree, keep)
    assert saved == ['a.npz.ckpt.npz (300 evaluations)', 'b.npz (400 evaluations)']
    assert (keep / 'c.npz.ckpt.npz').read_bytes() == kept_c
    assert not (keep / 'b.npz.ckpt.npz').exists()  # the map finished: its checkpoint goes
    assert (keep / 'a.npz.log.jsonl').read_text() == '{"evaluations": 5}\n'
    with np.load(keep / 'a.npz.ckpt.npz') as data:
        assert 'centroids' not in data.files
    assert (keep / 'a.npz.ckpt.npz').stat().st_size < (runs / 'a.npz.ckpt.npz').stat().st_size / 2

    fresh = tmp_path / 'new-machine'
    (fresh / 'hexapod_adapt' / 'maps').mkdir(parents=True)
    shutil.copyfile(DEMO_MAP, fresh / progress.DEFAULT_MAP)
    restored = progress.restore(fresh, keep)
    assert sorted(restored) == [
        'a.npz.ckpt.npz (300 evaluations)',
        'b.npz (400 evaluations)',
        'c.npz.ckpt.npz (200 evaluations)',
    ]
    again, pending = load_checkpoint(fresh / progress.RUNS / 'a.npz.ckpt.npz')
    before, pending_before = load_checkpoint(runs / 'a.npz.ckpt.npz')
    for name in ('centroids', 'fitness', 'genotypes', 'descriptors'):
        np.testing.assert_array_equal(getattr(again, name), getattr(before, name))
    assert again.metadata == before.metadata
    assert pending.keys() == pending_before.keys()
    assert progress.restore(fresh, keep) == []  # nothing further on than what is there now
    assert progress.save(tree, keep) == []  # nor here
