# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The shipped default map: its size, its provenance, and that this installation can use it."""

import json

from hexapod_adapt.mapping.archive import compatibility_problems, load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, DEMO_MAP, shipped_map
from hexapod_adapt.mapping.simulation import archive_engine
from hexapod_adapt.online.run_config import expected_metadata
import numpy as np


def test_the_default_map_is_full_scale_and_fits_this_installation():
    path = shipped_map(DEFAULT_MAP)
    archive = load_archive(path)  # checks the file's integrity (ArchiveError otherwise)
    assert archive.n_niches >= 10_000
    assert archive.metadata['evaluations'] >= 1_000_000
    assert archive_engine(archive.metadata) == 'mujoco'
    assert archive.n_filled > 0.5 * archive.n_niches
    assert np.all(np.isfinite(archive.fitness[archive.filled]))
    # adapt_node refuses a map whose URDF, gait mapping or trial duration differ from this
    # installation's; the shipped one must pass in every mode
    for mode in ('sim', 'robot', 'manual'):
        assert compatibility_problems(archive, expected_metadata(mode)) == [], mode


def test_the_default_map_log_covers_the_whole_run():
    path = shipped_map(DEFAULT_MAP)
    log = path.with_name(path.name + '.log.jsonl')
    rows = [json.loads(line) for line in log.read_text().splitlines() if line.strip()]
    evaluations = [row['evaluations'] for row in rows]
    assert evaluations == sorted(evaluations)
    assert evaluations[-1] == load_archive(path).metadata['evaluations']


def test_the_demo_map_is_still_shipped_for_tests():
    assert load_archive(shipped_map(DEMO_MAP)).n_filled > 0
