# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A damage-informed prior that streams: the map re-scored under the damage, its best gaits first.

A full re-score takes one evaluation per gait (minutes on 2 cores for the default map:
``adapt_prior_rescore_s`` in docs/benchmarks.md), and an operator should not wait for it.
:class:`StreamingPrior` scores the gaits in the order of their intact speed, in the background;
the first trial starts once the top ``first`` are scored, and the rest update M-BOA's prior
between trials (a session's ``SessionStart.updates``). A gait not yet scored is given its intact
speed times the median ratio of damaged to intact speed over the gaits scored so far. When every
gait is scored the ceiling is cached, as :func:`hexapod_adapt.online.ceiling.ceiling` caches it,
so the next run is instant.
"""

from __future__ import annotations

import concurrent.futures as cf
from dataclasses import dataclass
import os
import threading
import time
from typing import Callable, Sequence

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.mapping.simulation import engine_of_map
from hexapod_adapt.online.bank import BANK_DAMAGES, DamageBank, load_banks, RESCORE_WHEN_NAMED
from hexapod_adapt.online.ceiling import (
    cached_ceiling,
    Ceiling,
    estimate_unwalked,
    evaluate_part,
    intact_order,
    Rescoring,
    store_ceiling,
    TOP_FIRST,
)
from hexapod_adapt.online.diagnosis import GapCalibration, HypothesisWalks
from hexapod_adapt.online.session import diagnosis_plan, DiagnosisPlan, PriorStart
from hexapod_sim.damage import Damage
from hexapod_util.processes import die_with_parent, result_unless_stopped, Stopped, worker_pool
import numpy as np

#: Gaits per pool job: small enough that the prior refreshes between trials.
CHUNK = 64
#: The re-score's processes yield the cores to the trials (a simulator walking in fast mode lost
#: odometry to a re-score at the same priority on 2 cores).
NICENESS = 10


class _Closed(Exception):
    """Raised inside the re-score's pool when it is closed: the pool ends its workers at once."""


def _lower_priority() -> None:
    die_with_parent()
    os.nice(NICENESS)


@dataclass(frozen=True)
class PriorSnapshot:
    """The prior as far as the re-score has come."""

    speeds: np.ndarray  # (elites,) m/s, in the order of archive.elite_indices()
    scored: int  # gaits scored under the damage
    total: int
    seconds: float  # since the re-score began

    @property
    def complete(self) -> bool:
        """Return True when every gait is scored."""
        return self.scored == self.total


class StreamingPrior:
    """The map re-scored under ``damage`` on ``engine`` in the background, best gaits first."""

    def __init__(
        self,
        archive: Archive,
        damage: Damage,
        engine: str,
        cache_dir: str | os.PathLike | None,
        read_dirs: Sequence[str | os.PathLike] = (),
        workers: int = 1,
        first: int = TOP_FIRST,
        progress: Callable[[int, int], None] | None = None,
    ) -> None:
        self.archive, self.damage, self.engine = archive, damage, engine
        self.cache_dir, self.progress = cache_dir, progress
        niches = archive.elite_indices()
        self._intact = archive.speeds()[niches]
        self.total = len(niches)
        self.first = min(first, self.total)
        self._speeds = np.full(self.total, np.nan)
        self._scored = 0
        self._seen = -1  # what update() last handed out
        self._cond = threading.Condition()
        self._stop = False
        self.error = ''
        self._t0 = time.monotonic()
        dirs = [*read_dirs] + ([cache_dir] if cache_dir is not None else [])
        cached = cached_ceiling(archive, damage, engine, dirs)
        if cached is not None:
            self._speeds, self._scored, self.cached = cached.speeds.copy(), self.total, True
            return
        self.cached = False
        order = intact_order(archive)
        self._thread = threading.Thread(
            target=self._run, args=(order, workers), name='streaming-prior', daemon=True
        )
        self._thread.start()

    def _run(self, order: np.ndarray, workers: int) -> None:
        genes = self.archive.genotypes[self.archive.elite_indices()]
        parts = np.array_split(order, range(CHUNK, len(order), CHUNK))
        how = Rescoring.of(self.archive, self.damage, self.engine)
        try:
            # closed, the pool's workers are ended at once (worker_pool), not after their chunks:
            # the next run's re-score gets the cores
            with worker_pool(max(1, workers), initializer=_lower_priority) as pool:
                futures = [pool.submit(evaluate_part, (how, genes[idx])) for idx in parts]
                for idx, future in zip(parts, futures):
                    speeds = self._result_of(future)
                    with self._cond:
                        if self._stop:
                            raise _Closed
                        self._speeds[idx] = speeds
                        self._scored += len(idx)
                        self._cond.notify_all()
                    if self.progress is not None:
                        self.progress(self._scored, self.total)
        except _Closed:
            return
        except Exception as exc:  # a broken pool or engine: the runs go on with what is scored
            with self._cond:
                self.error = f'the re-score stopped: {type(exc).__name__}: {exc}'
                self._cond.notify_all()
            return
        if self._scored == self.total:
            niches = self.archive.elite_indices()
            result = Ceiling(self.damage, self.engine, niches, self._speeds.copy())
            store_ceiling(self.archive, result, self.cache_dir)

    def _result_of(self, future: cf.Future) -> np.ndarray:
        """Return a chunk's speeds once walked; raise _Closed as soon as the re-score is closed."""
        try:
            return result_unless_stopped(future, lambda: self._stop)
        except Stopped:
            raise _Closed from None

    def wait_first(self, timeout: float) -> bool:
        """Wait until the top ``first`` gaits are scored; False on a timeout or a failure."""
        with self._cond:
            return (
                self._cond.wait_for(
                    lambda: self._scored >= self.first or bool(self.error) or self._stop, timeout
                )
                and self._scored >= self.first
            )

    def snapshot(self) -> PriorSnapshot:
        """Return the prior now: scored gaits as scored, the others estimated."""
        return self._snapshot(take=False)

    def take(self) -> PriorSnapshot:
        """Return the prior now, as :meth:`snapshot`; :meth:`update` then waits for more."""
        return self._snapshot(take=True)

    def _snapshot(self, take: bool) -> PriorSnapshot:
        with self._cond:
            speeds, scored = self._speeds.copy(), self._scored
            if take:
                self._seen = scored
        speeds = estimate_unwalked(self._intact, speeds)
        return PriorSnapshot(speeds, scored, self.total, time.monotonic() - self._t0)

    def update(self) -> np.ndarray | None:
        """Return the prior if more gaits were scored since the last call, else None."""
        with self._cond:
            if self._scored == self._seen:
                return None
        return self.take().speeds

    @property
    def stopped(self) -> bool:
        """Return True once :meth:`close` was called."""
        return self._stop

    def close(self) -> None:
        """Stop scoring now, and end its workers (what is scored is kept; nothing is cached)."""
        with self._cond:
            self._stop = True
            self._cond.notify_all()


#: How long a run waits for the top of the map to be re-scored before its first trial [s].
PRIOR_FIRST_TIMEOUT = 600.0


class StreamingPriors:
    """
    adapt_node's source of damage-informed priors (a session's ``PriorSource``).

    Each run's damage is re-scored on the map's engine, best gaits first, read from
    ``read_dirs`` and ``cache_dir`` when cached; a re-score still streaming for the same map and
    damage is the next run's too. Progress goes to ``log`` every ``progress_period`` s.
    """

    def __init__(
        self,
        cache_dir: str | None,
        read_dirs: Sequence[str | os.PathLike],
        workers: int,
        log: Callable[[str], None],
        progress_period: float = 5.0,
        bank: Sequence[Damage] = BANK_DAMAGES,
        wider: Sequence[Damage] | None = None,
        rescore_when_named: bool = RESCORE_WHEN_NAMED,
    ) -> None:
        self.cache_dir, self.read_dirs, self.workers = cache_dir, list(read_dirs), workers
        self.bank_damages = tuple(bank)  # what a blind run's diagnosis weighs, where cached
        self.wider_damages = None if wider is None else tuple(wider)  # once none of those fits
        self.rescore_when_named = rescore_when_named  # the damages not cached weighed too
        self.log, self.progress_period = log, progress_period
        self.stream: StreamingPrior | None = None  # the last run's (may still stream)
        #: the robot's gap to the map's engine, taken out of every blind run's hypotheses
        self.calibration: GapCalibration | None = None
        self._walks: HypothesisWalks | None = None  # the hypotheses' walks, kept across runs
        self._bank: DamageBank | None = None
        self._banked: Archive | None = None  # the map _bank and _wider are of
        self._wider: DamageBank | None = None

    def start(self, archive: Archive, damage: Damage, source: str) -> PriorStart:
        """Wait for the top of the re-score under ``damage``; return the run's PriorStart."""
        stream = self._stream_for(archive, damage)
        if not stream.wait_first(PRIOR_FIRST_TIMEOUT):
            if stream.error:
                why = stream.error
            elif stream.stopped:  # the node shutting down, before the timeout
                why = 'the re-score was stopped before the top of the map was scored'
            else:
                why = f'the top of the map was not re-scored in {PRIOR_FIRST_TIMEOUT:.0f} s'
            return PriorStart(None, f'the map as it is ({why}; damage from {source})')
        snap = stream.take()  # one snapshot: the speeds and what is said of them agree
        what = f'the map re-scored on {stream.engine} under {damage.label}'
        if stream.cached:
            how = 'cached'
        elif snap.complete:
            how = f'{snap.seconds:.0f} s'
        else:
            how = (
                f'streaming: the best {snap.scored} of {snap.total} gaits scored in'
                f' {snap.seconds:.0f} s before the first trial, the rest update the prior'
                ' between trials'
            )
        best = float(np.max(snap.speeds))
        note = f'{what} (best {best:.3f} m/s, {how}), from {source}'
        return PriorStart(snap.speeds, note, stream.update)

    def diagnosis(self, archive: Archive, tip_guard: float) -> DiagnosisPlan | None:
        """
        Return a blind run's diagnosis over the bank (None: the bank weighs nothing).

        The bank is the map under each of ``bank_damages`` (the lifted legs of S1-S4 unless told
        otherwise), and ``wider_damages``, read from ``read_dirs`` and ``cache_dir``; with
        ``rescore_when_named``, those not cached too (re-scored when named). The hypotheses'
        walks are kept across runs, and :attr:`calibration` (when set) takes the robot's gap to
        the engine out of them.
        """
        if self._banked is not archive:
            engine = engine_of_map(archive)
            dirs = [*self.read_dirs] + ([self.cache_dir] if self.cache_dir else [])
            self._bank, self._wider = load_banks(
                archive,
                engine,
                dirs,
                self.bank_damages,
                self.wider_damages,
                self.rescore_when_named,
            )
            self._banked = archive
        return diagnosis_plan(
            archive,
            self._bank,
            tip_guard,
            walks=self.walks(archive),
            wider=self._wider,
            calibration=self.calibration,
            workers=self.workers,
        )

    def walks(self, archive: Archive) -> HypothesisWalks:
        """Return the walks the diagnosis of runs on ``archive`` compares trials with."""
        if self._walks is None or self._walks.archive is not archive:
            self._walks = HypothesisWalks(archive, engine_of_map(archive), self.workers)
        return self._walks

    def close(self) -> None:
        """Stop a re-score still streaming."""
        if self.stream is not None:
            self.stream.close()

    def _stream_for(self, archive: Archive, damage: Damage) -> StreamingPrior:
        """Return the re-score under ``damage``: the one still streaming, or a new one."""
        s = self.stream
        if s is not None and s.archive is archive and s.damage == damage:
            if not (s.error or s.stopped):
                return s
        self.close()
        engine = engine_of_map(archive)
        shown = [time.monotonic()]

        def progress(done: int, total: int) -> None:
            if time.monotonic() - shown[0] >= self.progress_period or done == total:
                shown[0] = time.monotonic()
                self.log(
                    f're-scoring the map under {damage.label}: {done}/{total} gaits'
                    f' ({100 * done / total:.0f} %)'
                    + (', complete and cached' if done == total else '')
                )

        self.stream = StreamingPrior(
            archive,
            damage,
            engine,
            self.cache_dir,
            self.read_dirs,
            self.workers,
            progress=progress,
        )
        if not self.stream.cached:
            self.log(
                f'damage-informed prior: re-scoring {archive.n_filled} gaits on {engine} under'
                f' {damage.label}, the best {self.stream.first} first'
            )
        return self.stream
