# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The pyribs emitter sets a map may be made with, and their settings (no pyribs import).

Kept apart from :mod:`hexapod_adapt.mapping.emitters`, which imports pyribs (and through it
scikit-learn, pandas and numba: seconds of start-up): the nodes and commands that only read a
map's settings never load it.
"""

from __future__ import annotations

from dataclasses import dataclass

#: The emitter sets generate_map offers ('iso_line' is map_elites' own, the thesis's operator).
EMITTER_SETS = ('iso_line', 'cma_me', 'cma_mae', 'bandit')


@dataclass(frozen=True)
class EmitterSettings:
    """How an emitter set is built (part of a map's identity, recorded in its metadata)."""

    name: str  # one of EMITTER_SETS
    count: int = 5  # emitters per lane (the bandit: active ones, from a pool of 3 x count)
    batch: int = 36  # solutions per emitter per ask
    sigma0: float = 0.15  # CMA-ES's initial step size (genes in [0, 1])
    lanes: int = 2  # schedulers asked in turn, so workers never wait for a batch's tail
    learning_rate: float = 0.01  # CMA-MAE's archive learning rate
    iso_sigma: float = 0.01  # iso+line (the bandit's pool): pymap_elites' values
    line_sigma: float = 0.2

    def __post_init__(self) -> None:
        if self.name not in EMITTER_SETS or self.name == 'iso_line':
            raise ValueError(f'emitter set must be one of {", ".join(EMITTER_SETS[1:])}')
        if self.count < 1 or self.batch < 1 or self.lanes < 1:
            raise ValueError('emitters, batch and lanes must be >= 1')
        if not (0.0 < self.sigma0 <= 1.0 and 0.0 < self.learning_rate <= 1.0):
            raise ValueError('sigma0 and the learning rate must be in (0, 1]')

    @property
    def batch_size(self) -> int:
        """Candidates per lane's ask."""
        return self.count * self.batch
