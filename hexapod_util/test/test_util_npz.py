# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The .npz reader under damage: truncations, bit flips, foreign and hostile contents.

Every outcome is the arrays asked for or an UnreadableFile that names the file, never another
exception (a node that loads a damaged map, bank or cache must say so and keep running).
"""

from __future__ import annotations

import io

from hexapod_util.npz import float_array, json_array, read_npz, UnreadableFile
from hypothesis import given, HealthCheck, settings
from hypothesis import strategies as st
import numpy as np
import pytest

NAMES = ('key', 'values')


def _blob() -> bytes:
    buf = io.BytesIO()
    rng = np.random.default_rng(0)
    np.savez_compressed(buf, key=np.array('{"a": [1, 2]}'), values=rng.normal(size=(50, 3)))
    return buf.getvalue()


BLOB = _blob()


def _outcome(path) -> str:
    try:
        data = read_npz(path, NAMES)
        json_array(data['key'], 'key')
        float_array(data['values'], 'values')
        return 'read'
    except UnreadableFile as exc:
        assert str(path) in str(exc) or 'key' in str(exc) or 'values' in str(exc)
        return 'refused'


def test_a_good_file_reads_and_every_truncation_is_refused(tmp_path):
    good = tmp_path / 'good.npz'
    good.write_bytes(BLOB)
    assert _outcome(good) == 'read'
    assert json_array(read_npz(good, NAMES)['key'], 'key') == {'a': [1, 2]}
    cut = tmp_path / 'cut.npz'
    for length in range(0, len(BLOB), max(1, len(BLOB) // 300)):
        cut.write_bytes(BLOB[:length])
        assert _outcome(cut) == 'refused', length


@settings(
    max_examples=600,
    derandomize=True,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(bits=st.lists(st.integers(0, 8 * len(BLOB) - 1), min_size=1, max_size=3))
def test_bit_flips_give_the_arrays_or_an_unreadable_file(tmp_path, bits):
    data = bytearray(BLOB)
    for bit in bits:
        data[bit // 8] ^= 1 << (bit % 8)
    path = tmp_path / 'flipped.npz'
    path.write_bytes(bytes(data))
    _outcome(path)  # raises anything but UnreadableFile


def test_missing_foreign_and_hostile_contents_are_said(tmp_path):
    with pytest.raises(FileNotFoundError):
        read_npz(tmp_path / 'absent.npz', NAMES)
    np.save(tmp_path / 'one.npy', np.zeros(3))
    with pytest.raises(UnreadableFile, match='a single array, not an .npz archive'):
        read_npz(tmp_path / 'one.npy', NAMES)
    np.savez(tmp_path / 'other.npz', key=np.array('{}'))
    with pytest.raises(UnreadableFile, match='missing values'):
        read_npz(tmp_path / 'other.npz', NAMES)
    assert set(read_npz(tmp_path / 'other.npz', ('key',), ('values', 'x'))) == {'key'}
    np.savez(tmp_path / 'pickled.npz', key=np.array([{'a': 1}], dtype=object))
    with pytest.raises(UnreadableFile, match='truncated or corrupted'):
        read_npz(tmp_path / 'pickled.npz', ('key',))  # never unpickled
    for bad in (np.array('{'), np.array('[' * 100000), np.array([1.0]), np.array(b'\xff\xfe')):
        with pytest.raises(UnreadableFile, match='the key'):
            json_array(bad, 'the key')
    with pytest.raises(UnreadableFile, match='must hold numbers'):
        float_array(np.array(['1.0']), 'values')
