# Copyright 2026 Hexapod adaptation team
# All rights reserved.
#
# Permission is hereby granted, free of charge, to any person obtaining a copy
# of this software and associated documentation files (the "Software"), to deal
# in the Software without restriction, including without limitation the rights
# to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
# copies of the Software, and to permit persons to whom the Software is
# furnished to do so, subject to the following conditions:
#
# The above copyright notice and this permission notice shall be included in all
# copies or substantial portions of the Software.
#
# THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
# IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
# FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
# AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
# LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
# OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
# SOFTWARE.
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
