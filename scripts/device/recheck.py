# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Walk some gaits of a ceiling case cached elsewhere again, to compare this machine's speeds.

    python3 scripts/device/recheck.py MAP CACHE_DIR DAMAGE [WORKERS] [GAITS]

DAMAGE as ``ceilings_cli --damage`` takes it (``1:lifted``). Before cases made on another machine
join a cache: the same physics gives the same speeds to ~1e-10 m/s (the order of the sums).
Exits 1 if the case is not cached in CACHE_DIR or a speed differs by more than 1e-6 m/s.
"""

from __future__ import annotations

import sys

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.online.ceiling import cached_ceiling, compute_ceiling
from hexapod_sim.damage import parse_damage
import numpy as np

TOLERANCE = 1e-6  # [m/s]


def main(argv: list[str]) -> int:
    """Re-walk GAITS (160) gaits spread over the cached case; print the largest difference."""
    map_path, cache_dir, spec = argv[:3]
    workers = int(argv[3]) if len(argv) > 3 else 1
    gaits = int(argv[4]) if len(argv) > 4 else 160
    archive = load_archive(map_path)
    damage = parse_damage(spec)
    kept = cached_ceiling(archive, damage, 'mujoco', [cache_dir])
    if kept is None:
        print(f'recheck: {damage.label} of {map_path} is not cached in {cache_dir}')
        return 1
    niches = kept.niches[:: max(1, len(kept.niches) // gaits)][:gaits]
    again = compute_ceiling(archive, damage, 'mujoco', workers, chunk=8, niches=niches)
    diff = np.abs(again.speeds - kept.speeds[np.searchsorted(kept.niches, niches)])
    print(
        f'recheck: {len(niches)} gaits of {damage.label} walked again, largest speed difference'
        f' {diff.max():.3g} m/s ({int((diff > 0).sum())} differ at all)'
    )
    return 0 if diff.max() <= TOLERANCE else 1


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
