# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The gap calibration's file and its making from a run's trials (online.calibration)."""

from __future__ import annotations

from dataclasses import replace
import io
import json

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
from hexapod_adapt.online.calibration import gap_from_trials, gap_key, load_gap, save_gap
from hexapod_adapt.online.diagnosis import (
    feature_names,
    feature_noise,
    GapCalibration,
    HypothesisWalks,
)
from hexapod_sim.damage import Damage
from hexapod_util.npz import UnreadableFile
from hypothesis import given, HealthCheck, settings
from hypothesis import strategies as st
import numpy as np
import pytest

NAMES = feature_names(False)


@pytest.fixture(scope='module')
def archive():
    return load_archive(shipped_map(DEFAULT_MAP))


@pytest.fixture(scope='module')
def key(archive):
    return gap_key(archive, 'mujoco')


def _calibration(roll: float = 0.03) -> GapCalibration:
    offset = np.zeros(len(NAMES))
    offset[NAMES.index('roll')] = roll
    return GapCalibration(offset, feature_noise(NAMES) * 1.5)


def test_a_saved_calibration_reads_back_whole_and_only_against_its_engine(archive, key, tmp_path):
    path = save_gap(_calibration(), tmp_path / 'gap.npz', key, 3)
    got, gaits = load_gap(path, key)
    assert gaits == 3 and not got.contacts
    np.testing.assert_array_equal(got.offset, _calibration().offset)
    np.testing.assert_array_equal(got.noise, _calibration().noise)
    with pytest.raises(ValueError, match='other walks') as other:
        load_gap(path, gap_key(archive, 'pybullet'))
    assert 'engine' in str(other.value) and 'calibrate again' in str(other.value)
    with pytest.raises(FileNotFoundError):
        load_gap(tmp_path / 'none.npz', key)
    # rewritten atomically: the last good file stays whole until the new one replaces it
    save_gap(_calibration(0.05), path, key, 4)
    assert load_gap(path, key)[1] == 4


def _write(path, **arrays) -> None:
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    path.write_bytes(buf.getvalue())


def test_a_file_that_is_no_calibration_is_refused_saying_what_is_wrong(key, tmp_path):
    good = {
        'key': np.array(json.dumps(key)),
        'offset': _calibration().offset,
        'noise': _calibration().noise,
        'contacts': np.array(0),
        'gaits': np.array(3),
    }
    cases = {
        'missing noise': ({k: v for k, v in good.items() if k != 'noise'}, 'missing noise'),
        'a nan offset': ({**good, 'offset': np.full(len(NAMES), np.nan)}, 'finite'),
        'a short offset': ({**good, 'offset': np.zeros(3)}, 'features'),
        'text noise': ({**good, 'noise': np.array(['a'] * len(NAMES))}, 'numbers'),
        'one gait': ({**good, 'gaits': np.array(1)}, 'two gaits'),
        'another format': ({**good, 'key': np.array(json.dumps({'format': 9}))}, 'format'),
        'a key not json': ({**good, 'key': np.array('{')}, 'JSON'),
    }
    for name, (arrays, says) in cases.items():
        path = tmp_path / f'{name}.npz'
        _write(path, **arrays)
        with pytest.raises(ValueError, match=says):
            load_gap(path, key)
    (tmp_path / 'cut.npz').write_bytes(b'PK\x03\x04' + b'\x00' * 40)
    with pytest.raises(UnreadableFile, match='corrupted'):
        load_gap(tmp_path / 'cut.npz', key)


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(data=st.binary(max_size=600), cut=st.integers(0, 2000))
def test_any_bytes_read_as_a_calibration_or_refused_with_a_value_error(key, tmp_path, data, cut):
    path = tmp_path / 'fuzz.npz'
    whole = io.BytesIO()
    np.savez(whole, key=np.array(json.dumps(key)), offset=np.zeros(len(NAMES)))
    path.write_bytes(whole.getvalue()[:cut] + data)  # a real file cut short and garbage
    try:
        load_gap(path, key)
    except ValueError:
        pass


@pytest.mark.slow
def test_a_run_s_intact_trials_measure_the_robot_s_bias_against_the_engine(archive):
    """An IMU mounted 2 deg off in roll: the intact walks of three gaits measure it."""
    walks = HypothesisWalks(archive)
    niches = archive.elite_indices()
    fastest = niches[np.argsort(-archive.fitness[niches], kind='stable')][:3]
    bias = np.radians(2.0)
    trials = []
    for niche in fastest:
        record = walks(int(niche), Damage.lifted(()))
        trials.append((int(niche), replace(record, attitude=record.attitude + [bias, 0, 0])))
    gap, used = gap_from_trials(walks, trials)
    assert used == 3
    expect = np.zeros(len(NAMES))
    expect[NAMES.index('roll')] = bias
    np.testing.assert_allclose(gap.offset, expect, atol=1e-9)
    with pytest.raises(ValueError, match='two or more'):
        gap_from_trials(walks, trials[:1])
