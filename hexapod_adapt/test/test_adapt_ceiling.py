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
"""The map's ceiling under a damage: against a brute-force loop, cached, never trusted blindly."""

from __future__ import annotations

from hexapod_adapt.archive import Archive, load_archive
from hexapod_adapt.ceiling import cache_path, ceiling, ceiling_key, compute_ceiling
from hexapod_adapt.maps import DEMO_MAP, shipped_map
from hexapod_sim import create_simulator, evaluate_gait, SimConfig
import numpy as np
import pytest


@pytest.fixture(scope='module')
def small_map() -> Archive:
    demo = load_archive(shipped_map(DEMO_MAP))
    keep = demo.elite_indices()[:12]
    small = Archive(
        demo.centroids,
        np.full(len(demo.centroids), np.nan),
        demo.descriptors.copy(),
        demo.genotypes.copy(),
        dict(demo.metadata),
    )
    small.fitness[keep] = demo.fitness[keep]
    return small


def test_the_ceiling_is_every_gait_evaluated_with_the_damage(small_map):
    legs = (1, 4)
    with create_simulator(SimConfig(engine='mujoco')) as sim:
        brute = [
            evaluate_gait(
                small_map.genotypes[n], sim, collisions_fatal=False, failed_legs=legs
            ).speed
            for n in small_map.elite_indices()
        ]
    result = compute_ceiling(small_map, legs, 'mujoco', workers=2, chunk=5)
    assert result.niches.tolist() == small_map.elite_indices().tolist()
    np.testing.assert_array_equal(result.speeds, brute)
    assert result.best_speed == max(brute) and result.beating(max(brute)) == 0
    assert result.best_niche == small_map.elite_indices()[int(np.argmax(brute))]
    assert result.beating(-1.0) == len(brute)


def test_a_cached_ceiling_is_reused_and_a_damaged_one_recomputed(small_map, tmp_path):
    first = ceiling(small_map, [2], 'mujoco', cache_dir=tmp_path)
    path = cache_path(tmp_path, ceiling_key(small_map, [2], 'mujoco'))
    assert path.is_file()
    stamp = path.stat().st_mtime_ns
    again = ceiling(small_map, [2], 'mujoco', cache_dir=tmp_path)
    np.testing.assert_array_equal(first.speeds, again.speeds)
    assert path.stat().st_mtime_ns == stamp  # read, not written again
    path.write_bytes(path.read_bytes()[:100])  # damaged on disk
    fixed = ceiling(small_map, [2], 'mujoco', cache_dir=tmp_path)
    np.testing.assert_array_equal(first.speeds, fixed.speeds)
    other = ceiling_key(small_map, [3], 'mujoco')
    assert cache_path(tmp_path, other) != path  # another damage, another file
