# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A map's stored speed as what a gait walks across physics variants (issue 66, deliverable 2).

With :class:`RobustScore` a map walks every proposed gait in K physics variants
(:func:`hexapod_sim.variants.draw_variants`, the same K for the whole map, drawn from the score's
seed) and stores a low statistic of the K distances: the gait a map keeps is one that walks in
every variant, not one that is fast in one model. The study that chooses K and the statistic is
studies/robust_speed/README.md.

A gait that collides or fails its walk guards in any variant fails (collisions are fatal in a
map: a physics we cannot rule out makes it collide). Its descriptor is the mean of its
variants' duty factors; its peak tilt the largest of theirs.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Sequence

from hexapod_sim import SimConfig
from hexapod_sim.evaluation import EvaluationResult, failure
from hexapod_sim.variants import draw_variants, variant_config
import numpy as np


def _mean_minus_std(x: np.ndarray) -> float:
    return float(np.mean(x) - np.std(x))


#: The statistics a map may store (the study's candidates), over a gait's K distances [m].
STATISTICS: dict[str, Callable[[np.ndarray], float]] = {
    'min': lambda x: float(np.min(x)),
    'q25': lambda x: float(np.quantile(x, 0.25)),
    'mean-std': _mean_minus_std,
}


@dataclass(frozen=True)
class RobustScore:
    """K physics variants per gait, stored by ``statistic`` (``variants`` 0: the model alone)."""

    variants: int = 0
    statistic: str = 'min'
    seed: int = 0

    def __post_init__(self) -> None:
        if isinstance(self.variants, bool) or not isinstance(self.variants, int):
            raise ValueError(f'variants must be an integer, got {self.variants!r}')
        if not 0 <= self.variants <= 256:
            raise ValueError(f'variants must be in [0, 256], got {self.variants}')
        if self.statistic not in STATISTICS:
            raise ValueError(
                f'statistic must be one of {", ".join(STATISTICS)}, got {self.statistic!r}'
            )
        if not (isinstance(self.seed, int) and 0 <= self.seed < 2**32):
            raise ValueError(f'variant seed must be in [0, 2^32), got {self.seed!r}')

    @property
    def active(self) -> bool:
        """Whether gaits are walked in variants (not in the model alone)."""
        return self.variants > 0

    def configs(self, base: SimConfig) -> list[SimConfig]:
        """Return the variants' simulator configurations (``base`` alone when not active)."""
        if not self.active:
            return [base]
        return [variant_config(base, v) for v in draw_variants(self.variants, self.seed)]

    def fingerprint(self) -> dict[str, Any]:
        """Return what the stored speed depends on (recorded in the map's metadata)."""
        return {
            'variants': self.variants,
            'statistic': self.statistic,
            'seed': self.seed,
            'physics': [v.as_dict() for v in draw_variants(self.variants, self.seed)],
        }

    def combine(self, walks: Sequence[EvaluationResult]) -> EvaluationResult:
        """
        Return one gait's result from its walks in the variants (in variant order).

        The walks end at the first that failed, if one did (the gait walks no further).
        """
        for k, walk in enumerate(walks):
            if not walk.valid:
                reason = f'in physics variant {k}: {walk.reason}'
                return failure(reason, walk.duration)
        distances = np.array([w.fitness for w in walks])
        return EvaluationResult(
            STATISTICS[self.statistic](distances),
            np.mean([w.descriptor for w in walks], axis=0),
            True,
            '',
            walks[0].duration,
            sum(w.collision_steps for w in walks),
            None,
            sum(w.seconds for w in walks),
            max(w.peak_tilt for w in walks),
        )
