# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Emitter sets from pyribs (``ribs``), fed by the asynchronous worker pool of map_elites.

pyribs implements the emitters: CMA-ME's improvement emitters (Fontaine et al. 2020, CMA-ES
inside the archive), CMA-MAE's annealed archive (Fontaine and Nikolaidis 2023), the iso+line
operator, and a UCB1 bandit over a mixed pool (Multi-Emitter MAP-Elites, Cully 2021). pyribs
asks and tells in whole batches, one batch at a time. What it lacks, written here:

* **Lanes.** ``lanes`` schedulers, each with its own emitters, share one pyribs archive.
  Batch j (candidates j*B .. (j+1)*B - 1, B the batch size) belongs to lane j mod lanes and is
  asked as soon as batch j - lanes has been told: while one lane waits for the last results of
  its batch, the workers evaluate the others'. Results are told in candidate order, so the map
  depends only on the seed and the settings, never on the worker count or their timing.
* **Invalid gaits** (the thesis's fitness 0, no descriptor) are told to their emitter as not
  added, and never enter an archive.
* **Checkpoints.** The whole state (lanes, archive, the batch being told) is one picklable
  object, stored in the run's checkpoint, so a resumed run continues exactly.

The result map is always the run's own :class:`~hexapod_adapt.mapping.archive.Archive` (the
file format); the pyribs archive guides the emitters (for CMA-MAE it is the annealed one).
"""

from __future__ import annotations

import pickle
from typing import Sequence

from hexapod_adapt.mapping.emitter_settings import EmitterSettings
import numpy as np
from ribs.archives import CVTArchive
from ribs.emitters import EvolutionStrategyEmitter, IsoLineEmitter
from ribs.schedulers import BanditScheduler, Scheduler

#: The objective an archive never takes (an invalid gait), for the ranking of a batch.
_INVALID = -np.inf


class ValidOnlyCVTArchive(CVTArchive):
    """A pyribs CVT archive that leaves out the rows whose ``valid`` field is false."""

    def __init__(self, **kwargs) -> None:
        super().__init__(extra_fields={'valid': ((), np.bool_)}, **kwargs)

    def add(self, solution, objective, measures, valid=None, **fields):  # noqa: D102 (pyribs')
        objective = np.asarray(objective, dtype=float)
        keep = np.ones(len(objective), bool) if valid is None else np.asarray(valid, bool)
        status = np.zeros(len(objective), dtype=np.int32)
        value = np.full(len(objective), _INVALID)
        if keep.any():
            info = super().add(
                np.asarray(solution)[keep],
                objective[keep],
                np.asarray(measures)[keep],
                valid=keep[keep],
                **{k: np.asarray(v)[keep] for k, v in fields.items()},
            )
            status[keep], value[keep] = info['status'], info['value']
        return {'status': status, 'value': value}


class RibsProposer:
    """Candidates from pyribs emitter sets, in lanes (see the module docstring)."""

    def __init__(
        self,
        settings: EmitterSettings,
        centroids: np.ndarray,
        genes: int,
        seed: int,
        seen: Sequence[tuple[np.ndarray, float, np.ndarray]] = (),
    ) -> None:
        """``seen``: (genes, fitness, descriptor) already in the map, to start the archive."""
        self.settings = settings
        ss = np.random.SeedSequence([seed, 7])
        archive_seed, *lane_seeds = ss.spawn(1 + settings.lanes)
        mae = settings.name == 'cma_mae'
        self.archive = ValidOnlyCVTArchive(
            solution_dim=genes,
            centroids=np.asarray(centroids, dtype=float),
            ranges=[(0.0, 1.0)] * np.asarray(centroids).shape[1],
            learning_rate=settings.learning_rate if mae else None,
            threshold_min=-1.0 if mae else -np.inf,
            seed=int(archive_seed.generate_state(1)[0]),
        )
        if seen:
            g, f, d = (np.array(x, dtype=float) for x in zip(*seen))
            self.archive.add(g, f, d, valid=np.ones(len(f), bool))
        self.lanes = [self._scheduler(s, genes) for s in lane_seeds]
        self.batch = settings.batch_size
        self.first = 0  # the candidate number of batch 0 (after presets and random ones)
        self._results: list[tuple[np.ndarray, float, np.ndarray]] = []  # the batch being told
        self._asked: dict[int, np.ndarray] = {}  # candidates of asked batches not yet handed out

    def _scheduler(self, seed: np.random.SeedSequence, genes: int):
        s = self.settings
        seeds = iter(int(x.generate_state(1)[0]) for x in seed.spawn(3 * s.count))
        bounds = [(0.0, 1.0)] * genes

        def cma(ranker: str = '2imp', **kw) -> EvolutionStrategyEmitter:
            return EvolutionStrategyEmitter(
                self.archive,
                x0=np.full(genes, 0.5),
                sigma0=s.sigma0,
                ranker=ranker,
                bounds=bounds,
                batch_size=s.batch,
                seed=next(seeds),
                **kw,
            )

        if s.name == 'cma_me':
            return Scheduler(self.archive, [cma() for _ in range(s.count)])
        if s.name == 'cma_mae':
            mae = [cma('imp', selection_rule='mu', restart_rule='basic') for _ in range(s.count)]
            return Scheduler(self.archive, mae)
        pool = [cma() for _ in range(s.count)] + [cma('2rd') for _ in range(s.count)]
        pool += [
            IsoLineEmitter(
                self.archive,
                iso_sigma=s.iso_sigma,
                line_sigma=s.line_sigma,
                x0=np.full(genes, 0.5),  # only while the archive is empty (it never is here)
                bounds=bounds,
                batch_size=s.batch,
                seed=next(seeds),
            )
            for _ in range(s.count)
        ]
        return BanditScheduler(self.archive, pool, num_active=s.count)

    # -- the candidate protocol of map_elites --------------------------------------------------
    def may_ask(self, k: int, told: int) -> bool:
        """Whether candidate k may be asked now that ``told`` results are in."""
        batch, told_batches = (k - self.first) // self.batch, (told - self.first) // self.batch
        return batch < told_batches + len(self.lanes)

    def candidate(self, k: int) -> np.ndarray:
        """Return candidate k's genes (its lane is asked for the whole batch at the first)."""
        if k not in self._asked:
            batch = (k - self.first) // self.batch
            start = self.first + batch * self.batch
            solutions = np.clip(self.lanes[batch % len(self.lanes)].ask(), 0.0, 1.0)
            self._asked.update({start + i: s for i, s in enumerate(solutions)})
        return self._asked.pop(k)

    def tell(self, k: int, genes: np.ndarray, fitness: float, descriptor: np.ndarray) -> None:
        """Take candidate k's result (NaN fitness: invalid); a full batch goes to its lane."""
        self._results.append((genes, fitness, descriptor))
        if len(self._results) < self.batch:
            return
        lane = ((k - self.first) // self.batch) % len(self.lanes)
        _, f, d = zip(*self._results)
        self._results = []
        f = np.array(f, dtype=float)
        valid = np.isfinite(f)
        self.lanes[lane].tell(np.where(valid, f, 0.0), np.array(d, dtype=float), valid=valid)

    def add_seen(self, genes: np.ndarray, fitness: float, descriptor: np.ndarray) -> None:
        """Put a result that no lane asked for (a preset, a random gait) in the archive."""
        if np.isfinite(fitness):
            self.archive.add(genes[None], [fitness], descriptor[None], valid=[True])

    # -- checkpoints ---------------------------------------------------------------------------
    def dumps(self) -> bytes:
        """Return the whole state as bytes (stored in the run's checkpoint)."""
        return pickle.dumps(self, protocol=pickle.HIGHEST_PROTOCOL)

    @staticmethod
    def loads(blob: bytes) -> RibsProposer:
        """Return the state :meth:`dumps` saved."""
        state = pickle.loads(blob)  # noqa: S301 - written by this tool into its own checkpoint
        if not isinstance(state, RibsProposer):
            raise ValueError('the checkpoint holds no emitter state')
        return state
