# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The navigation repertoire: a step map ready for planning (ROS-free).

A step map (:mod:`hexapod_adapt.mapping.steps`, made by ``generate_map --kind navigation``)
indexes omnidirectional gaits by the body's displacement after one step; :class:`Repertoire`
holds its elites as arrays for the planner.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from hexapod_adapt import (
    Archive,
    ArchiveError,
    DEFAULT_MAP_ENGINE,
    engine_of_map,
    from_descriptor,
    gait_min_stance,
    shipped_map,
)
from hexapod_gait import GaitParameters
from hexapod_gait.parameters import from_omni_genotype
import numpy as np

PACKAGE = 'hexapod_navigation'
NAVIGATION_MAP = 'navigation_map.npz'  # the shipped repertoire (maps/make_navigation_map.sh)


def shipped_repertoire() -> Path:
    """Return where the shipped repertoire is (installed, else the source tree)."""
    return shipped_map(NAVIGATION_MAP, PACKAGE)


@dataclass(frozen=True)
class Repertoire:
    """
    A navigation repertoire ready for planning: its elites as arrays.

    ``moves`` (n, 2) is each elite's displacement [m] in its start frame after one step of
    ``step_duration`` s; ``heading_error`` (n,) the size of its heading change [rad] (the sign is
    not stored; the navigator learns it). ``niches`` (n,) are the archive rows.
    """

    niches: np.ndarray
    moves: np.ndarray
    heading_error: np.ndarray
    genotypes: np.ndarray
    step_duration: float
    digest: str
    engine: str = DEFAULT_MAP_ENGINE  # the engine that measured the steps (the map's)

    @classmethod
    def from_archive(cls, archive: Archive) -> 'Repertoire':
        """Return the repertoire of a navigation archive; ArchiveError for any other map."""
        if archive.kind.name != 'navigation':
            raise ArchiveError(
                f'a {archive.kind.name} map is not a navigation repertoire (make one with'
                ' generate_map --kind navigation)'
            )
        idx = archive.elite_indices()
        if idx.size == 0:
            raise ArchiveError('the navigation repertoire holds no gait')
        return cls(
            idx,
            from_descriptor(archive.descriptors[idx]),
            -archive.fitness[idx],
            archive.genotypes[idx],
            archive.trial_duration,
            archive.metadata['centroid_hash'][:12],
            engine_of_map(archive),
        )

    def __len__(self) -> int:
        return len(self.niches)

    def min_stance(self) -> np.ndarray:
        """Return, per elite, the fewest feet on the ground at any instant of its cycle (n,)."""
        return np.array([gait_min_stance(self.gait(i)) for i in range(len(self))])

    def gait(self, i: int) -> GaitParameters:
        """Return elite ``i`` (a row of the arrays, not a niche) as gait parameters."""
        return from_omni_genotype(self.genotypes[i], archive_index=int(self.niches[i]))
