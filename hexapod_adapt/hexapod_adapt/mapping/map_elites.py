# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
CVT-MAP-Elites (thesis algorithm 1, 4.2), asynchronous and reproducible; ROS-free.

Candidates are numbered k = 0, 1, 2, ... Candidate k's genes come from its own random stream
``default_rng([seed, k])`` and from the archive as it stands after the results of candidates
0 .. k - lag - 1 have been inserted (results are inserted strictly in candidate order, however
they finish). So up to ``lag + 1`` evaluations are in flight at any time -- no worker waits for a
batch to finish -- and the map depends only on (seed, configuration), not on the number of
workers, the executor (process pool, Dask, MPI) or their timing. A checkpoint stores the
archive plus the candidates in flight, so a resumed run continues exactly.

Variation is pymap_elites' iso+line operator: x = x1 + sigma_iso * N(0, I) + sigma_line *
N(0, 1) * (x2 - x1), clipped to [0, 1], with x1, x2 two random elites. Until ``random_init`` of
the niches are filled, candidates are random genotypes (thesis 4.2.4: 1 %). Optional
``initial`` genotypes (e.g. the hand-designed preset gaits) are the first candidates.
Invalid gaits (unreachable, colliding, body on the ground: the thesis's fitness 0, empty
descriptor) are counted as evaluations and not inserted.
"""

from __future__ import annotations

import concurrent.futures as cf
from dataclasses import asdict, dataclass
import json
import math
import os
import time
from typing import Callable, Protocol, Sequence, TYPE_CHECKING

from hexapod_adapt.mapping.archive import Archive, ArchiveError, InsertStatus, load_archive
from hexapod_adapt.mapping.emitter_settings import EMITTER_SETS, EmitterSettings
from hexapod_util.npz import read_npz, UnreadableFile
import numpy as np

if TYPE_CHECKING:  # pyribs loads in seconds: only a run with its emitters imports it
    from hexapod_adapt.mapping.emitters import RibsProposer


@dataclass(frozen=True)
class MapElitesConfig:
    """Settings of a MAP-Elites run; together with the seed they are the map's identity."""

    evaluations: int  # total evaluations, random initialisation included
    seed: int = 0
    lag: int = 64  # candidates in flight (>= workers, 2-4x workers keeps them busy)
    random_init: float = 0.01  # fraction of niches filled with random gaits first (thesis 4.2.4)
    sigma_iso: float = 0.01  # pymap_elites defaults
    sigma_line: float = 0.2
    chunk: int = 1  # candidates per task sent to a worker (larger over a network)
    initial: tuple[tuple[float, ...], ...] = ()  # genotypes tried first (e.g. the preset gaits)
    #: who proposes candidates after the random initialisation: 'iso_line' (the operator above),
    #: or a pyribs emitter set (mapping.emitters.EmitterSettings, its settings in ``emitter``)
    emitters: str = 'iso_line'
    emitter: tuple[tuple[str, float], ...] = ()  # EmitterSettings' fields other than defaults

    def __post_init__(self) -> None:
        if self.evaluations < 1:
            raise ValueError(f'evaluations must be >= 1, got {self.evaluations}')
        if self.lag < 1 or self.chunk < 1:
            raise ValueError(f'lag and chunk must be >= 1, got lag={self.lag}, chunk={self.chunk}')
        if not 0.0 <= self.random_init <= 1.0:
            raise ValueError(f'random_init must be a fraction in [0, 1], got {self.random_init}')
        if self.sigma_iso < 0 or self.sigma_line < 0:
            raise ValueError('sigma_iso and sigma_line must be >= 0')
        if self.emitters not in EMITTER_SETS:
            raise ValueError(f'emitters must be one of {", ".join(EMITTER_SETS)}')
        if self.emitters != 'iso_line':
            self.emitter_settings()  # ValueError names a bad one
        elif self.emitter:
            raise ValueError('emitter settings apply to a pyribs emitter set, not iso_line')
        sizes = {len(genes) for genes in self.initial}
        if len(sizes) > 1 or not all(0.0 <= g <= 1.0 for genes in self.initial for g in genes):
            raise ValueError('initial genotypes must all have the same number of genes, in [0, 1]')

    def emitter_settings(self) -> EmitterSettings:
        """Return the pyribs emitter set's settings (only for emitters other than iso_line)."""
        return EmitterSettings(self.emitters, **dict(self.emitter))

    def identity(self) -> dict:
        """
        Return the settings a map's metadata records (and a resumed run must match).

        The emitter fields only for a pyribs set: maps made before they existed keep their
        identity.
        """
        settings = asdict(self)
        if self.emitters == 'iso_line':
            settings.pop('emitters')
            settings.pop('emitter')
        else:
            settings['emitter'] = dict(self.emitter)
        return settings


class Evaluation(Protocol):
    """What MAP-Elites needs of one candidate's result (hexapod_sim's EvaluationResult is one)."""

    fitness: float
    descriptor: np.ndarray  # (the archive's descriptor dimension,)
    valid: bool
    seconds: float  # the worker's CPU time for this evaluation (utilisation, core time)
    peak_tilt: float  # the body's largest roll or pitch [rad] (NaN: not recorded)


EvaluateFn = Callable[[np.ndarray], Sequence[Evaluation]]  # (m, genes) -> m evaluations


class MapElites:
    """The archive update and candidate generation (no executor; see :func:`run_map_elites`)."""

    def __init__(
        self,
        archive: Archive,
        config: MapElitesConfig,
        random_genes: Callable[[np.random.Generator], np.ndarray] | None = None,
    ):
        from scipy.spatial import cKDTree

        self.archive = archive
        self.config = config
        self.size = archive.genotypes.shape[1]  # genes per genotype (the archive's mapping)
        for genes in config.initial:
            if len(genes) != self.size:
                raise ValueError(
                    f'initial genotypes have {len(genes)} genes; this archive holds {self.size}'
                )
        self.random_genes = random_genes or (lambda rng: rng.random(self.size))
        self._tree = cKDTree(archive.centroids)
        self.told = int(archive.metadata.get('evaluations') or 0)  # results inserted so far
        self.proposer: RibsProposer | None = None  # a pyribs emitter set, once it has started
        self.needed = max(1, math.ceil(config.random_init * archive.n_niches))

    def may_ask(self, k: int) -> bool:
        """Whether candidate k may be asked now (k - lag results told, or its lane's turn)."""
        if self.proposer is not None and k >= self.proposer.first:
            return self.proposer.may_ask(k, self.told)
        return k <= self.told + self.config.lag

    def niche_of(self, descriptors: np.ndarray) -> np.ndarray:
        """Niche indices of descriptors (nearest centroid)."""
        return self._tree.query(np.atleast_2d(descriptors))[1]

    def candidate(self, k: int) -> np.ndarray:
        """Genes of candidate k (call when exactly results 0 .. k - lag - 1 are told)."""
        if k < len(self.config.initial):
            return np.array(self.config.initial[k], dtype=float)
        if self.proposer is not None and k >= self.proposer.first:
            return self.proposer.candidate(k)
        rng = np.random.default_rng([self.config.seed, k])
        elites = self.archive.elite_indices()
        if len(elites) < self.needed:
            return self.random_genes(rng)
        if self.config.emitters != 'iso_line':  # the emitter set takes over from here
            self.proposer = self._start_proposer(k)
            return self.proposer.candidate(k)
        x1, x2 = self.archive.genotypes[rng.choice(elites, 2)]
        child = (
            x1
            + self.config.sigma_iso * rng.standard_normal(self.size)
            + self.config.sigma_line * rng.standard_normal() * (x2 - x1)
        )
        return np.clip(child, 0.0, 1.0)

    def _start_proposer(self, first: int) -> RibsProposer:
        from hexapod_adapt.mapping.emitters import RibsProposer

        a = self.archive
        seen = [(a.genotypes[i], a.fitness[i], a.descriptors[i]) for i in a.elite_indices()]
        proposer = RibsProposer(
            self.config.emitter_settings(), a.centroids, self.size, self.config.seed, seen
        )
        proposer.first = first
        return proposer

    def sync_metadata(self) -> None:
        """Record the evaluations done and the settings in the archive's metadata."""
        self.archive.metadata['evaluations'] = self.told
        self.archive.metadata['map_elites'] = self.config.identity()

    def tell(self, genes: np.ndarray, result: Evaluation) -> InsertStatus | None:
        """
        Insert one result (in candidate order).

        What the archive did with it (None for an invalid gait, which is counted and not inserted).
        """
        k = self.told
        self.told += 1
        if self.proposer is not None:
            fitness = result.fitness if result.valid else float('nan')
            descriptor = np.asarray(result.descriptor, dtype=float)
            if not result.valid:
                descriptor = np.zeros(self.archive.centroids.shape[1])
            if k >= self.proposer.first:
                self.proposer.tell(k, genes, fitness, descriptor)
            else:
                self.proposer.add_seen(genes, fitness, descriptor)
        if not result.valid:
            return None
        niche = int(self.niche_of(result.descriptor)[0])
        return self.archive.insert(
            niche, result.fitness, result.descriptor, genes, result.peak_tilt
        )


# -- checkpoints -------------------------------------------------------------------------------
def save_checkpoint(
    path: str | os.PathLike, engine: MapElites, pending: dict[int, np.ndarray]
) -> None:
    """
    Archive + the candidates in flight, atomically, in one file.

    An archive file with two extra arrays: any archive reader can open it.
    """
    engine.sync_metadata()
    ks = np.array(sorted(pending), dtype=np.int64)
    genes = np.array([pending[k] for k in ks]).reshape(len(ks), engine.size)
    extra = {'pending_index': ks, 'pending_genes': genes}
    if engine.proposer is not None:  # the emitter set's whole state, to continue exactly
        extra['emitter_state'] = np.frombuffer(engine.proposer.dumps(), dtype=np.uint8)
    engine.archive.save(path, extra)


def load_checkpoint(path: str | os.PathLike) -> tuple[Archive, dict[int, np.ndarray]]:
    """(archive, candidates in flight) from a checkpoint; ArchiveError if it is not one."""
    archive, pending, _ = load_checkpoint_state(path)
    return archive, pending


def load_checkpoint_state(
    path: str | os.PathLike,
) -> tuple[Archive, dict[int, np.ndarray], RibsProposer | None]:
    """(archive, candidates in flight, the emitter set's state if any) from a checkpoint."""
    archive = load_archive(path)
    try:
        data = read_npz(path, (), ('pending_index', 'pending_genes', 'emitter_state'))
    except (OSError, UnreadableFile) as exc:
        raise ArchiveError(f'{path}: cannot read the checkpoint ({exc})') from None
    if 'pending_index' not in data:
        raise ArchiveError(
            f'{path}: an archive, not a map-generation checkpoint (no pending candidates)'
        )
    index, genes = data['pending_index'], data.get('pending_genes', np.zeros((0, 0)))
    if (
        index.ndim != 1
        or index.dtype.kind not in 'iu'
        or genes.shape != (len(index), archive.genotypes.shape[1])
        or genes.dtype.kind != 'f'
    ):
        raise ArchiveError(
            f'{path}: its pending candidates are damaged (index {index.dtype} {index.shape},'
            f' genes {genes.dtype} {genes.shape})'
        )
    pending = {int(k): np.array(g) for k, g in zip(index, genes)}
    blob = data['emitter_state'].tobytes() if 'emitter_state' in data else None
    try:
        proposer = None
        if blob is not None:
            from hexapod_adapt.mapping.emitters import RibsProposer

            proposer = RibsProposer.loads(blob)
    except Exception as exc:  # noqa: BLE001 - any damage to the state is the same refusal
        raise ArchiveError(f'{path}: its emitter state cannot be read ({exc})') from None
    return archive, pending, proposer


# -- the run loop ------------------------------------------------------------------------------
@dataclass
class Progress:
    """One progress report of a run (one line of its JSON-lines log)."""

    evaluations: int
    filled: int
    coverage: float
    max: float  # noqa: A003 (the statistic)
    mean: float
    median: float
    p5: float
    qd_score: float
    evals_per_s: float
    utilisation: float  # worker CPU time / (workers x wall time) since the run started
    elapsed: float
    workers: int = 1  # the run's worker processes (wall time x workers = the cores it held)
    #: CPU seconds since the run started: the workers' evaluations and this loop's own thread
    #: (the emitters); what the run used, however busy the machine was with other work
    cpu_s: float = 0.0

    def log_row(self) -> str:
        """Return this report as one JSON line."""
        return json.dumps(
            {k: round(v, 6) if isinstance(v, float) else v for k, v in asdict(self).items()}
        )


def run_map_elites(
    archive: Archive,
    config: MapElitesConfig,
    evaluate: EvaluateFn,
    executor: cf.Executor | None = None,
    workers: int = 1,
    checkpoint: str | os.PathLike | None = None,
    checkpoint_every: float = 600.0,
    pending: dict[int, np.ndarray] | None = None,
    proposer: RibsProposer | None = None,
    on_progress: Callable[[Progress], None] | None = None,
    progress_every: float = 10.0,
    random_genes: Callable[[np.random.Generator], np.ndarray] | None = None,
) -> Archive:
    """
    Run until ``config.evaluations`` results are in.

    ``evaluate`` is called in the executor (or inline without one) on chunks of genes. ``pending``
    resumes a checkpoint's in-flight candidates. Checkpoints every ``checkpoint_every`` s and at
    the end. ``random_genes(rng)`` draws a random-initialisation genotype (default uniform; the
    hexapod uses :func:`reachable_random_genes`).
    """
    engine = MapElites(archive, config, random_genes)
    engine.proposer = proposer  # a checkpoint's emitter set, in the state it was saved in
    run = _Run(engine, config, evaluate, executor, workers, dict(pending or {}))
    run.resubmit()
    run.ask_allowed()
    last_ckpt = last_progress = run.t0
    while engine.told < config.evaluations:
        run.submit_new()
        run.collect()
        run.tell_ready()
        now = time.monotonic()
        if on_progress and now - last_progress >= progress_every:
            on_progress(run.progress())
            last_progress = now
        if checkpoint and now - last_ckpt >= checkpoint_every:
            save_checkpoint(checkpoint, engine, run.pending)
            last_ckpt = now
    engine.sync_metadata()
    if checkpoint:
        save_checkpoint(checkpoint, engine, {})
    if on_progress:
        on_progress(run.progress())
    return engine.archive


class _Run:
    """One run's candidates in flight: asked, submitted in chunks, told in candidate order."""

    def __init__(
        self,
        engine: MapElites,
        config: MapElitesConfig,
        evaluate: EvaluateFn,
        executor: cf.Executor | None,
        workers: int,
        pending: dict[int, np.ndarray],
    ) -> None:
        self.engine, self.config, self.evaluate = engine, config, evaluate
        self.executor, self.workers = executor, max(workers, 1)
        self.pending = pending  # candidate index -> genes, asked and not yet told
        self.asked = engine.told + len(pending)
        self.done: dict[int, Evaluation] = {}
        self.futures: dict[cf.Future, list[int]] = {}
        self.inline: list[list[int]] = []  # without an executor: chunks evaluated one per turn
        self.new: list[int] = []  # asked, not yet submitted
        self.t0, self.cpu0 = time.monotonic(), time.thread_time()
        self.busy = 0.0  # the evaluations' own seconds, summed
        self.told_at_start = engine.told

    def progress(self) -> Progress:
        """Return the run's progress so far."""
        s = self.engine.archive.stats()
        wall = max(time.monotonic() - self.t0, 1e-9)
        return Progress(
            self.engine.told,
            s.filled,
            s.coverage,
            s.max,
            s.mean,
            s.median,
            s.p5,
            s.qd_score,
            (self.engine.told - self.told_at_start) / wall,
            self.busy / (self.workers * wall),
            wall,
            self.workers,
            # inline, the evaluations ran in this thread: its CPU time holds them already
            (self.busy if self.executor is not None else 0.0) + time.thread_time() - self.cpu0,
        )

    def submit(self, ks: list[int]) -> None:
        """Send candidates ``ks`` to be evaluated (as one chunk)."""
        if self.executor is None:
            self.inline.append(ks)
        else:
            genes = np.array([self.pending[k] for k in ks])
            self.futures[self.executor.submit(self.evaluate, genes)] = ks

    def resubmit(self) -> None:
        """Submit again what a checkpoint had in flight."""
        resumed = sorted(self.pending)
        for i in range(0, len(resumed), self.config.chunk):
            self.submit(resumed[slice(i, i + self.config.chunk)])

    def submit_new(self) -> None:
        """Submit the candidates asked and not yet sent (a chunk that is not full)."""
        if self.new:
            self.submit(self.new[:])
            self.new.clear()

    def ask_allowed(self) -> None:
        """Ask every candidate the results so far allow; submit each full chunk."""
        # candidate k sees exactly the results 0 .. k - lag - 1: ask it right after that tell
        while self.asked < self.config.evaluations and self.engine.may_ask(self.asked):
            self.pending[self.asked] = self.engine.candidate(self.asked)
            self.new.append(self.asked)
            self.asked += 1
            if len(self.new) == self.config.chunk:
                self.submit_new()

    def collect(self) -> None:
        """Evaluate one inline chunk, or take the chunks that finished within 1 s."""
        if self.inline:
            ks = self.inline.pop(0)
            for k, r in zip(ks, self.evaluate(np.array([self.pending[k] for k in ks]))):
                self.done[k] = r
        elif self.futures:
            finished, _ = cf.wait(list(self.futures), timeout=1.0, return_when=cf.FIRST_COMPLETED)
            for fut in finished:
                ks = self.futures.pop(fut)
                for k, r in zip(ks, fut.result()):
                    self.done[k] = r

    def tell_ready(self) -> None:
        """Tell the results in candidate order, asking what each tell allows."""
        while self.engine.told in self.done:
            k = self.engine.told
            r = self.done.pop(k)
            self.busy += r.seconds
            self.engine.tell(self.pending.pop(k), r)
            self.ask_allowed()
