# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Offline map generation.

CVT + MAP-Elites + the simulated evaluation (MuJoCo by default, or PyBullet), on a local process
pool, a Dask cluster or MPI (ROS-free API behind ``generate_map``).

Writes the archive atomically to ``out``; while running, a checkpoint ``<out>.ckpt.npz`` (the
archive plus the candidates in flight) every ``checkpoint_every`` seconds, and one JSON line per
``log_every`` seconds to the log file. ``resume=True`` continues from the checkpoint exactly:
the map is a function of (seed, configuration) only, whatever the backend or worker count.
Without a checkpoint, ``resume=True`` with more evaluations continues a finished map ``out``.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
from dataclasses import dataclass
import functools
import json
import os
from pathlib import Path
from typing import Callable, Iterator

from hexapod_adapt.mapping.archive import (
    Archive,
    ArchiveError,
    compatibility_problems,
    load_archive,
    map_kind,
)
from hexapod_adapt.mapping.cvt import cached_cvt, cvt_cache_path
from hexapod_adapt.mapping.emitter_settings import EmitterSettings
from hexapod_adapt.mapping.map_elites import (
    load_checkpoint_state,
    MapElitesConfig,
    Progress,
    run_map_elites,
)
from hexapod_adapt.mapping.robust import RobustScore
from hexapod_adapt.mapping.simulation import (
    DEFAULT_MAP_ENGINE,
    SimulateGenotypes,
    simulation_fingerprint,
    WalkGuards,
)
from hexapod_adapt.mapping.steps import preset_genotypes, repertoire_fingerprint, SimulateSteps
from hexapod_gait import preset, PRESETS, to_genotype
from hexapod_sim import validate_engine
from hexapod_sim.sampling import random_reachable_genes
from hexapod_util.processes import worker_pool

BACKENDS = ('local', 'dask', 'mpi', 'inline')


#: Inclusive ranges of GenerateConfig's numbers, checked by it and by generate_map's options.
LIMITS = {
    'niches': (2, 10_000_000),
    'evaluations': (1, 10**12),
    'seed': (0, 2**32 - 1),
    'workers': (0, 4096),  # 0 = every core
    'lag': (0, 1_000_000),  # 0 = max(64, 4 x workers)
    'chunk': (0, 100_000),  # 0 = the engine's default
    'substeps': (0, 64),  # 0 = the engine's default
    'random_init': (0.0, 1.0),
    'cvt_samples': (1, 10**9),
    'emitter_count': (1, 64),  # emitters per lane (pyribs sets)
    'emitter_batch': (1, 10_000),  # solutions per emitter per ask
    'sigma0': (1e-4, 1.0),  # CMA-ES's initial step size
    'lanes': (1, 64),
}


@dataclass(frozen=True)
class GenerateConfig:
    """Everything a ``generate_map`` run needs; ValueError names a bad setting."""

    out: Path
    niches: int = 10000
    evaluations: int = 1_000_000
    seed: int = 0
    backend: str = 'local'
    workers: int = 0  # local: processes (0 = all cores); dask/mpi: for the figures
    scheduler: str | None = None  # dask scheduler address (None: a local Dask cluster)
    lag: int = 0  # candidates in flight (0: 4 x workers, at least 64)
    chunk: int = 0  # candidates per worker call (0: 8 for MuJoCo, 1 for PyBullet)
    engine: str = DEFAULT_MAP_ENGINE
    #: gait maps: the engine's physics steps per 240 Hz row (0: its default; map_sim_config)
    substeps: int = 0
    random_init: float = 0.01
    cvt_samples: int | None = None
    cvt_dir: Path | None = None  # cache centroids_<n>_6.dat here (default: next to out)
    checkpoint_every: float = 600.0
    log_every: float = 30.0
    log: Path | None = None  # default: <out>.log.jsonl
    resume: bool = False
    with_presets: bool = False  # try the preset gaits (control, tripod, wave, quadruped) first
    kind: str = 'gait'  # 'gait' (the thesis map) or 'navigation' (a repertoire, repertoire.py)
    #: navigation: only gaits that keep this many feet down throughout are elites (0: any)
    min_stance_legs: int = 0
    #: gait maps: what an elite must also do (feet on the ground on average, the body's tilt)
    guards: WalkGuards = WalkGuards()
    #: gait maps on MuJoCo: each gait walked in physics variants, stored by a low statistic
    robust: RobustScore = RobustScore()
    #: who proposes candidates after the random start: iso_line (the thesis's operator), or a
    #: pyribs emitter set (cma_me, cma_mae, bandit; mapping.emitters) with these settings
    emitters: str = 'iso_line'
    emitter_count: int = 5
    emitter_batch: int = 36
    sigma0: float = 0.15
    lanes: int = 2

    def __post_init__(self) -> None:
        try:
            map_kind(self.kind)
        except ArchiveError as exc:
            raise ValueError(str(exc)) from None
        if self.backend not in BACKENDS:
            raise ValueError(f'backend must be one of {", ".join(BACKENDS)}, got {self.backend!r}')
        for name, (low, high) in LIMITS.items():
            value = getattr(self, name)
            if value is not None and not low <= value <= high:
                raise ValueError(f'{name} must be in [{low:g}, {high:g}], got {value!r}')
        for name in ('checkpoint_every', 'log_every'):
            if not getattr(self, name) > 0:
                raise ValueError(f'{name} must be > 0 s, got {getattr(self, name)!r}')
        validate_engine(self.engine)
        if not (isinstance(self.min_stance_legs, int) and 0 <= self.min_stance_legs <= 6):
            raise ValueError(f'min_stance_legs must be 0..6, got {self.min_stance_legs!r}')
        if self.min_stance_legs and self.kind != 'navigation':
            raise ValueError('min_stance_legs applies to navigation repertoires only')
        if self.substeps and self.kind != 'gait':
            raise ValueError('substeps applies to gait maps only')
        if self.guards.active and self.kind != 'gait':
            raise ValueError('walk guards (min_feet, max_tilt) apply to gait maps only')
        if self.robust.active and (self.kind != 'gait' or self.engine != 'mujoco'):
            raise ValueError('physics variants (--variants) apply to gait maps on MuJoCo only')
        self.engine_config()  # the MAP-Elites settings' own checks (emitters, ...)

    @property
    def checkpoint_path(self) -> Path:
        """Return the checkpoint file beside the output (``<out>.ckpt.npz``)."""
        return Path(f'{self.out}.ckpt.npz')

    @property
    def log_path(self) -> Path:
        """Return the JSON-lines progress log (``<out>.log.jsonl`` unless set)."""
        return self.log or Path(f'{self.out}.log.jsonl')

    def worker_count(self) -> int:
        """Worker processes to use (every core the process may run on if 0)."""
        if self.workers:
            return self.workers
        if hasattr(os, 'sched_getaffinity'):
            return len(os.sched_getaffinity(0))
        return os.cpu_count() or 1

    def engine_config(self) -> MapElitesConfig:
        # MuJoCo evaluates a chunk as one native batch; PyBullet gains nothing from batches.
        """Return the MAP-Elites settings this run implies (chunk and lag defaults resolved)."""
        chunk = self.chunk or (8 if self.engine == 'mujoco' else 1)
        lag = self.lag or max(64, 4 * chunk * self.worker_count())
        emitter: tuple = ()
        if self.emitters != 'iso_line':
            # the lanes keep the workers busy; the random start's lag is then a setting too, so
            # that the map does not depend on the worker count
            lag = self.lag or self.lanes * self.emitter_count * self.emitter_batch
            defaults = EmitterSettings(self.emitters)
            wanted = {
                'count': self.emitter_count,
                'batch': self.emitter_batch,
                'sigma0': self.sigma0,
                'lanes': self.lanes,
            }
            emitter = tuple((k, v) for k, v in wanted.items() if getattr(defaults, k) != v)
        initial: tuple = ()
        if self.with_presets and self.kind == 'navigation':
            initial = preset_genotypes()
        elif self.with_presets:
            initial = tuple(tuple(float(g) for g in to_genotype(preset(name))) for name in PRESETS)
        return MapElitesConfig(
            evaluations=self.evaluations,
            seed=self.seed,
            lag=lag,
            random_init=self.random_init,
            chunk=chunk,
            initial=initial,
            emitters=self.emitters,
            emitter=emitter,
        )


@contextlib.contextmanager
def open_executor(config: GenerateConfig) -> Iterator[tuple[cf.Executor | None, int]]:
    """(executor, worker count) for the configured backend."""
    if config.backend == 'inline':
        yield None, 1
    elif config.backend == 'local':
        n = config.worker_count()
        with worker_pool(n) as pool:  # a stop ends its workers at once
            yield pool, n
    elif config.backend == 'dask':
        try:
            from distributed import Client, LocalCluster
        except ImportError as exc:  # pragma: no cover - dask is in requirements.txt
            raise RuntimeError("the dask backend needs the 'distributed' package") from exc
        if config.scheduler:
            client = Client(config.scheduler)
            cluster = None
        else:
            cluster = LocalCluster(
                n_workers=config.worker_count(),
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
            )
            client = Client(cluster)
        try:
            n = len(client.scheduler_info()['workers']) or config.worker_count()
            yield client.get_executor(pure=False), n
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    else:  # mpi: mpiexec -n N python -m mpi4py.futures -m hexapod_adapt.mapping.generate_map_cli
        try:
            from mpi4py.futures import MPIPoolExecutor
        except ImportError as exc:
            raise RuntimeError(
                "the mpi backend needs mpi4py and an MPI library (e.g. Debian's openmpi-bin "
                'libopenmpi-dev, then pip install mpi4py)'
            ) from exc
        with MPIPoolExecutor() as pool:
            yield pool, config.workers or pool.num_workers


def remove_orphaned_temporaries(out: Path) -> list[Path]:
    """
    Delete the temporary files an interrupted atomic write left beside ``out``; return them.

    Those are ``.<name>.*.tmp`` files of ``out`` or of its checkpoint.
    """
    removed = []
    for name in (out.name, f'{out.name}.ckpt.npz'):
        for tmp in out.parent.glob(f'.{name}.*.tmp'):
            with contextlib.suppress(FileNotFoundError):
                tmp.unlink()
                removed.append(tmp)
    return removed


class EmptyMapError(RuntimeError):
    """The run finished without a single valid gait: no map was written."""


def _check_resumable(source: Path, archive: Archive, engine, fingerprint: dict) -> None:
    """Refuse (ArchiveError) to resume ``source`` with other settings, physics or fewer evals."""
    saved = archive.metadata.get('map_elites', {})
    # Candidate k depends on (seed, k, lag, settings) and the results before it, never on the
    # total: a run may be resumed with MORE evaluations and equals a run made that long at once.
    wanted = json.loads(json.dumps(engine.identity()))  # as stored: tuples became lists
    differ = sorted(
        k for k in set(saved) | set(wanted) if k != 'evaluations' and saved.get(k) != wanted.get(k)
    )
    if saved and differ:

        def show(settings: dict, key: str) -> str:
            value = settings.get(key)
            return f'{len(value)} genotypes' if key == 'initial' else repr(value)

        raise ArchiveError(
            f'{source}: written with other MAP-Elites settings ('
            + '; '.join(f'{k} {show(saved, k)}, not {show(wanted, k)}' for k in differ)
            + '): resume with the same --seed/--lag/--chunk/--random-init/--with-presets'
            '/--engine/--kind/--emitters and emitter settings'
        )
    if saved and engine.evaluations < archive.metadata.get('evaluations', 0):
        raise ArchiveError(
            f'{source}: already has {archive.metadata["evaluations"]}'
            f' evaluations, more than the {engine.evaluations} asked for'
        )
    problems = compatibility_problems(archive, fingerprint)
    if problems:
        raise ArchiveError(
            f'{source}: cannot resume a map made with another simulator,'
            ' engine or URDF: ' + '; '.join(problems)
        )


def _empty_archive(config: GenerateConfig, dim: int, fingerprint: dict) -> Archive:
    """Return a new run's empty archive on its CVT (one per study, as in the thesis)."""
    # reused from centroids_<n>_<dim>.dat when present
    cvt_dir = Path(config.cvt_dir or Path(config.out).parent)
    cvt_file = cvt_cache_path(cvt_dir, config.niches, dim)
    reused = cvt_file.is_file()
    centroids = cached_cvt(
        cvt_dir, config.niches, dim, samples=config.cvt_samples, seed=config.seed
    )
    cvt_info = {'file': cvt_file.name, 'reused': reused}
    if not reused:
        cvt_info.update(samples=config.cvt_samples or 25 * config.niches, seed=config.seed)
    return Archive.empty(
        centroids, {'seed': config.seed, 'evaluations': 0, **fingerprint, 'cvt': cvt_info}
    )


def generate_map(
    config: GenerateConfig, on_progress: Callable[[Progress], None] | None = None
) -> Archive:
    """
    Run (or resume) a map generation; returns the final archive (also written to config.out).

    Raises EmptyMapError if no evaluated gait was valid (nothing is written then).
    """
    out = Path(config.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    remove_orphaned_temporaries(out)
    kind = map_kind(config.kind)
    if kind.name == 'navigation':
        fingerprint = repertoire_fingerprint(config.engine, config.min_stance_legs)
        evaluate = SimulateSteps(config.engine, config.min_stance_legs)
    else:
        fingerprint = simulation_fingerprint(
            config.engine, config.guards, config.substeps, config.robust
        )
        evaluate = SimulateGenotypes(config.engine, config.guards, config.substeps, config.robust)
    engine = config.engine_config()
    pending, proposer = None, None
    source = None  # the file a resumed run continues
    if config.resume and config.checkpoint_path.is_file():
        source = config.checkpoint_path
        archive, pending, proposer = load_checkpoint_state(source)
    elif config.resume and out.is_file():
        # a finished map without its checkpoint: no candidate was in flight when it finished, so
        # it continues from its archive (not bit-identical to one longer run: the first lag
        # candidates after it see the final archive)
        source = out
        archive, pending, proposer = load_archive(out), {}, None
    if source is not None:
        _check_resumable(source, archive, engine, fingerprint)
    else:
        archive = _empty_archive(config, kind.descriptor_dim, fingerprint)
    log_path = config.log_path
    log_path.parent.mkdir(parents=True, exist_ok=True)
    with open_executor(config) as (executor, workers):

        def progress(p: Progress) -> None:
            # opened per row: a file replaced under a long run (git checkout, a copy) still gets it
            with open(log_path, 'a', encoding='utf-8') as log:
                log.write(p.log_row() + '\n')
            if on_progress:
                on_progress(p)

        archive = run_map_elites(
            archive,
            engine,
            evaluate,
            executor=executor,
            workers=workers,
            checkpoint=config.checkpoint_path,
            checkpoint_every=config.checkpoint_every,
            pending=pending,
            proposer=proposer,
            on_progress=progress,
            progress_every=config.log_every,
            random_genes=functools.partial(random_reachable_genes, size=kind.genotype_size),
        )
    if archive.n_filled == 0:
        raise EmptyMapError(
            f'no valid gait in {archive.metadata.get("evaluations")} evaluations: no map written '
            f'(the checkpoint {config.checkpoint_path} holds the run)'
        )
    archive.metadata.pop('created', None)
    archive.save(out)
    return archive
