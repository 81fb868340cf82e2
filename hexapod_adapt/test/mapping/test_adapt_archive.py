# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Archive file: round trip, atomic writes, clear errors, thesis text format."""

from hexapod_adapt.mapping.archive import (
    Archive,
    ArchiveError,
    compatibility_problems,
    export_thesis_map,
    import_thesis_map,
    load_archive,
    load_centroids,
    save_centroids,
)
import numpy as np
import pytest


def _archive(n=50, filled=20, seed=3):
    rng = np.random.default_rng(seed)
    a = Archive.empty(rng.random((n, 6)), {'seed': seed, 'evaluations': 123})
    idx = rng.choice(n, filled, replace=False)
    a.fitness[idx] = rng.normal(0.5, 0.3, filled)
    a.descriptors[idx] = rng.random((filled, 6))
    a.genotypes[idx] = rng.random((filled, 32))
    return a


def test_round_trip_keeps_every_value_and_metadata(tmp_path):
    a = _archive()
    path = a.save(tmp_path / 'map.npz')
    b = load_archive(path)
    for name in ('centroids', 'fitness', 'descriptors', 'genotypes'):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert b.metadata['seed'] == 3 and b.metadata['evaluations'] == 123
    assert b.metadata['niches'] == 50 and b.metadata['format_version'] == 1
    assert b.metadata['genotype_mapping'] == 'thesis-4.1/v1' and 'created' in b.metadata
    assert b.n_filled == 20 and b.stats().filled == 20
    np.testing.assert_allclose(b.speeds()[b.filled], b.fitness[b.filled] / 5.0)
    assert [p.name for p in tmp_path.iterdir()] == ['map.npz']  # no temporary left behind


def test_truncated_and_foreign_files_are_refused_with_reasons(tmp_path):
    path = _archive().save(tmp_path / 'map.npz')
    data = path.read_bytes()
    cut = tmp_path / 'cut.npz'
    cut.write_bytes(data[: len(data) // 2])
    with pytest.raises(ArchiveError, match='truncated or corrupted'):
        load_archive(cut)
    with pytest.raises(ArchiveError, match='no such archive'):
        load_archive(tmp_path / 'missing.npz')
    other = tmp_path / 'other.npz'
    np.savez(other, x=np.zeros(3))
    with pytest.raises(ArchiveError, match='not a hexapod archive'):
        load_archive(other)


def test_a_failed_save_keeps_the_previous_file(tmp_path, monkeypatch):
    good = _archive(seed=1)
    path = good.save(tmp_path / 'map.npz')
    before = path.read_bytes()

    def disk_full(*args, **kwargs):
        raise OSError(28, 'No space left on device')

    monkeypatch.setattr('os.replace', disk_full)
    with pytest.raises(OSError):
        _archive(seed=2).save(path)
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ['map.npz']


def test_inconsistent_contents_are_refused():
    with pytest.raises(ArchiveError, match='genotypes must have shape'):
        Archive(np.zeros((4, 6)), np.zeros(4), np.zeros((4, 6)), np.zeros((4, 31)))
    with pytest.raises(ArchiveError, match='in \\[0, 1\\]'):
        Archive(
            np.zeros((2, 6)), np.array([1.0, np.nan]), np.full((2, 6), 0.5), np.full((2, 32), 1.5)
        )
    with pytest.raises(ArchiveError, match='niche 1 has a fitness'):
        Archive(
            np.zeros((2, 6)),
            np.array([np.nan, 1.0]),
            np.full((2, 6), np.nan),
            np.full((2, 32), 0.5),
        )


def test_altered_centroids_are_detected(tmp_path):
    path = _archive().save(tmp_path / 'map.npz')
    with np.load(path) as d:
        arrays = {k: d[k] for k in d.files}
    arrays['centroids'] = arrays['centroids'] * 0.5
    np.savez(tmp_path / 'altered.npz', **arrays)
    with pytest.raises(ArchiveError, match='centroid hash'):
        load_archive(tmp_path / 'altered.npz')


def test_compatibility_problems_name_the_mismatch():
    a = _archive()
    assert compatibility_problems(a, {'genotype_mapping': 'thesis-4.1/v1'}) == []
    problems = compatibility_problems(a, {'genotype_mapping': 'other/v9', 'urdf_sha256': 'abc'})
    assert len(problems) == 2 and 'other/v9' in problems[0] and 'urdf_sha256' in problems[1]


def test_thesis_text_format_round_trip_through_a_centroids_file(tmp_path):
    a = _archive(n=40, filled=15)
    save_centroids(tmp_path / 'centroids_40_6.dat', a.centroids)
    export_thesis_map(a, tmp_path / 'archive_1000.dat')
    rows = np.loadtxt(tmp_path / 'archive_1000.dat')
    assert rows.shape == (15, 45)
    b = import_thesis_map(
        tmp_path / 'archive_1000.dat', load_centroids(tmp_path / 'centroids_40_6.dat')
    )
    np.testing.assert_array_equal(a.fitness, b.fitness)
    np.testing.assert_array_equal(a.genotypes[a.filled], b.genotypes[b.filled])
    bare = import_thesis_map(tmp_path / 'archive_1000.dat')  # niches = the rows' centroids
    assert bare.n_niches == 15 and bare.n_filled == 15


def test_thesis_import_refuses_wrong_rows_and_foreign_centroids(tmp_path):
    bad = tmp_path / 'bad.dat'
    np.savetxt(bad, np.zeros((3, 44)))
    with pytest.raises(ArchiveError, match='45 numbers'):
        import_thesis_map(bad)
    a = _archive(n=40, filled=5)
    export_thesis_map(a, tmp_path / 'm.dat')
    with pytest.raises(ArchiveError, match='different centroids file'):
        import_thesis_map(tmp_path / 'm.dat', np.random.default_rng(9).random((40, 6)))


def test_a_map_of_some_niches_keeps_their_elites_alone():
    a = _archive()
    a.peak_tilt[a.filled] = 0.1
    keep = a.elite_indices()[[0, 3, 7]]
    small = a.only(keep)
    assert small.n_filled == 3 and list(small.elite_indices()) == sorted(keep)
    np.testing.assert_array_equal(small.fitness[keep], a.fitness[keep])
    np.testing.assert_array_equal(small.peak_tilt[keep], 0.1)
    assert np.isnan(small.peak_tilt[~small.filled]).all()
    np.testing.assert_array_equal(small.genotypes, a.genotypes)  # a copy: the rows kept
    small.genotypes[keep[0], 0] = -1.0
    assert a.genotypes[keep[0], 0] != -1.0
    empty = int(np.flatnonzero(~a.filled)[0])
    with pytest.raises(ValueError, match=rf'niches \[{empty}\] hold no elite'):
        a.only([keep[0], empty])


def test_insert_says_what_happened():
    from hexapod_adapt.mapping.archive import InsertStatus

    a = Archive.empty(np.full((2, 6), 0.5))
    d, g = np.full(6, 0.5), np.full(32, 0.5)
    assert a.insert(0, 1.0, d, g) is InsertStatus.NEW
    assert (
        a.insert(0, 0.5, d, np.zeros(32)) is InsertStatus.NOT_IMPROVED and a.genotypes[0, 0] == 0.5
    )
    # a tie keeps the incumbent
    assert a.insert(0, 1.0, d, np.zeros(32)) is InsertStatus.NOT_IMPROVED
    assert a.insert(0, 2.0, d, np.zeros(32)) is InsertStatus.IMPROVED and a.fitness[0] == 2.0
    s = a.stats()
    assert (s.filled, s.coverage, s.max, s.qd_score) == (1, 0.5, 2.0, 2.0)


def test_peak_tilt_round_trips_and_a_map_without_it_reads_as_unrecorded(tmp_path):
    a = _archive()
    elites = a.elite_indices()
    a.peak_tilt[elites] = np.linspace(0.0, 1.0, len(elites))
    b = load_archive(a.save(tmp_path / 'map.npz'))
    np.testing.assert_array_equal(a.peak_tilt, b.peak_tilt)
    # a map written before peak tilts were kept: its file has no such array
    with np.load(tmp_path / 'map.npz') as data:
        old = {k: data[k] for k in data.files if k != 'peak_tilt'}
    np.savez(tmp_path / 'old.npz', **old)
    assert np.isnan(load_archive(tmp_path / 'old.npz').peak_tilt).all()
    # an insert keeps the elite's tilt; a result that does not record one leaves NaN
    c = Archive.empty(a.centroids)
    c.insert(0, 1.0, np.full(6, 0.5), np.full(32, 0.5), 0.25)
    c.insert(1, 1.0, np.full(6, 0.5), np.full(32, 0.5))
    assert c.peak_tilt[0] == 0.25 and np.isnan(c.peak_tilt[1:]).all()
    for bad, match in ((np.full(50, -0.1), '>= 0 rad'), (np.full(50, 4.0), 'at most pi'),
                       (np.zeros(49), r'shape \(50,\)')):  # fmt: skip
        np.savez(tmp_path / 'bad.npz', **{**old, 'peak_tilt': bad})
        with pytest.raises(ArchiveError, match=match):
            load_archive(tmp_path / 'bad.npz')
