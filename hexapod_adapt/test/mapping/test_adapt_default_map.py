# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The shipped default map: its size, its provenance, and that this installation can use it."""

import json
from pathlib import Path
import re

from hexapod_adapt.mapping.archive import compatibility_problems, load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, DEMO_MAP, shipped_map
from hexapod_adapt.mapping.simulation import archive_engine
from hexapod_adapt.online.run_config import expected_metadata
import numpy as np

WS = Path(__file__).resolve().parents[3]
KEYS = ('niches', 'evaluations', 'seed', 'engine', 'substeps')
#: The commit a map in the making is pinned at (resume_default_map.sh; removed when it ships).
IN_THE_MAKING = WS / 'hexapod_adapt' / 'maps' / 'in_progress' / 'COMMIT'


def test_the_default_map_is_the_one_its_script_makes_and_fits_this_installation():
    path = shipped_map(DEFAULT_MAP)
    archive = load_archive(path)  # checks the file's integrity (ArchiveError otherwise)
    # make_default_map.sh is the one home of its size, engine and step
    script = (WS / 'hexapod_adapt' / 'maps' / 'make_default_map.sh').read_text()
    asked = {k: re.search(rf'--{k} (\w+)', script).group(1) for k in KEYS}
    if IN_THE_MAKING.is_file():  # the script makes the next map; the shipped one is smaller
        assert 10_000 <= archive.n_niches <= int(asked['niches'])
        assert archive.metadata['evaluations'] < int(asked['evaluations'])
    else:
        assert archive.n_niches == int(asked['niches']) >= 10_000
        assert archive.metadata['evaluations'] == int(asked['evaluations'])
    assert archive.metadata['seed'] == int(asked['seed'])
    assert archive_engine(archive.metadata) == asked['engine']
    assert archive.metadata['simulator']['settings']['substeps'] == int(asked['substeps'])
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
