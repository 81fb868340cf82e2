# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The archive loader under damage: truncations, random bit flips, hostile contents.

Every outcome is a loaded archive or an ArchiveError that names the file -- never another
exception.
"""

from __future__ import annotations

import io
import json

from hexapod_adapt.mapping.archive import Archive, ArchiveError, load_archive
import numpy as np
import pytest


def _good(tmp_path):
    rng = np.random.default_rng(0)
    a = Archive.empty(rng.random((40, 6)), {'seed': 1, 'evaluations': 10})
    a.fitness[:20] = rng.random(20)
    a.descriptors[:20] = rng.random((20, 6))
    a.genotypes[:20] = rng.random((20, 32))
    path = a.save(tmp_path / 'good.npz')
    return path, path.read_bytes()


def _load_or_archive_error(path) -> str:
    try:
        load_archive(path)
        return 'loaded'
    except ArchiveError as exc:
        assert str(path) in str(exc)
        return 'refused'


def test_every_truncation_is_an_archive_error(tmp_path):
    path, blob = _good(tmp_path)
    bad = tmp_path / 'bad.npz'
    for length in list(range(0, len(blob), max(1, len(blob) // 400))) + [len(blob) - 1]:
        bad.write_bytes(blob[:length])
        assert _load_or_archive_error(bad) == 'refused', length


def test_3000_random_bit_flips_give_an_archive_or_an_archive_error(tmp_path):
    path, blob = _good(tmp_path)
    bad = tmp_path / 'flipped.npz'
    rng = np.random.default_rng(2026)
    outcomes = {'loaded': 0, 'refused': 0}
    for _ in range(3000):
        data = bytearray(blob)
        for _ in range(int(rng.integers(1, 4))):
            bit = int(rng.integers(0, 8 * len(data)))
            data[bit // 8] ^= 1 << (bit % 8)
        bad.write_bytes(bytes(data))
        outcomes[_load_or_archive_error(bad)] += 1
    assert outcomes['refused'] > 0
    print(outcomes)


def _with(tmp_path, name='x.npz', meta_update=None, **arrays):
    path, _ = _good(tmp_path)
    with np.load(path) as d:
        content = {k: d[k] for k in d.files}
    meta = json.loads(str(content['metadata']))
    meta.update(meta_update or {})
    content['metadata'] = np.array(json.dumps(meta))
    content.update(arrays)
    buf = io.BytesIO()
    np.savez(buf, **content)
    out = tmp_path / name
    out.write_bytes(buf.getvalue())
    return out


@pytest.mark.parametrize(
    'duration', [0, 0.0, -5.0, float('nan'), float('inf'), '5', None, True, 1e9]
)
def test_nonsensical_trial_duration_is_refused(tmp_path, duration):
    path = _with(tmp_path, meta_update={'trial_duration': duration})
    with pytest.raises(ArchiveError, match='trial_duration must be a number of seconds'):
        load_archive(path)


def test_fitness_of_strings_is_refused(tmp_path):
    path = _with(tmp_path, fitness=np.array(['fast'] * 40))
    with pytest.raises(ArchiveError, match='fitness must hold numbers'):
        load_archive(path)


def test_metadata_that_is_not_a_json_object_is_refused(tmp_path):
    path, _ = _good(tmp_path)
    with np.load(path) as d:
        content = {k: d[k] for k in d.files}
    for meta in (np.array('[1, 2]'), np.array('{'), np.array([1.0, 2.0]), np.array('[' * 100000)):
        content['metadata'] = meta
        np.savez(tmp_path / 'm.npz', **content)
        with pytest.raises(ArchiveError):
            load_archive(tmp_path / 'm.npz')


def test_a_single_array_file_is_refused(tmp_path):
    np.save(tmp_path / 'one.npy', np.zeros(3))
    with pytest.raises(ArchiveError, match='not an .npz archive'):
        load_archive(tmp_path / 'one.npy')


def test_a_checkpoint_with_damaged_pending_candidates_is_refused(tmp_path):
    from hexapod_adapt.mapping.map_elites import load_checkpoint_state

    path, _ = _good(tmp_path)
    archive = load_archive(path)
    ckpt = tmp_path / 'map.npz.ckpt.npz'
    archive.save(ckpt, {'pending_index': np.array([3, 7]), 'pending_genes': np.ones((2, 32))})
    _, pending, proposer = load_checkpoint_state(ckpt)
    assert sorted(pending) == [3, 7] and proposer is None
    for index, genes in (
        (np.array([1.5]), np.ones((1, 32))),  # not whole numbers
        (np.array([1, 2]), np.ones((2, 5))),  # genes of another size
        (np.array([[1]]), np.ones((1, 32))),
        (np.array(['a']), np.ones((1, 32))),
        (np.array([1]), np.array([['x'] * 32])),
    ):
        archive.save(ckpt, {'pending_index': index, 'pending_genes': genes})
        with pytest.raises(ArchiveError, match='pending candidates are damaged'):
            load_checkpoint_state(ckpt)
    archive.save(ckpt)  # an archive, not a checkpoint
    with pytest.raises(ArchiveError, match='not a map-generation checkpoint'):
        load_checkpoint_state(ckpt)
