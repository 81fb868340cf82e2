# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The behaviour-performance map (archive) file: one self-describing ``.npz`` (ROS-free).

An archive has one row per niche (a CVT centroid in its descriptor space). Its metadata
``kind`` (:data:`MAP_KINDS`) says which space; a gait map (the thesis's, the default) is:

    centroids   (n, 6)   niche centres, 0..1
    fitness     (n,)     metres walked along the walking direction in ``trial_duration``
                         seconds (thesis 4.1.1); NaN where the niche is empty
    descriptors (n, 6)   measured duty factor per leg of the elite (eq. 4.2); NaN if empty
    genotypes   (n, 32)  the elite's genes, 0..1 (mapping ``genotype_mapping``); NaN if empty
    peak_tilt   (n,)     the elite's largest body roll or pitch in its trial [rad] (over every
                         physics variant that scored it); NaN if empty or not recorded (a map
                         made before 2026-12-03 has no such array)

A navigation repertoire (docs/navigation.md) has 2-D descriptors (the body's displacement in
its start frame, scaled to 0..1), 34-gene omni genotypes, and as fitness minus the heading
change [rad].

plus a JSON metadata record (format version, evaluations, seed, centroid hash, genotype
mapping version, URDF and simulator fingerprints, creation time, tool version, ...).
Files are written atomically: a temporary file in the same directory, fsync, rename, fsync of
the directory, so a crash or a full disk leaves the previous file intact.

The thesis / pymap_elites text format (``fitness, descriptor(6), centroid(6), genotype(32)``
per row, filled niches only) and ``centroids_<n>_<dim>.dat`` files import and export.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import datetime as _dt
import enum
import hashlib
import io
import json
import math
import os
from pathlib import Path
from typing import Any, Mapping, Sequence

from hexapod_gait import GENOTYPE_MAPPING_VERSION, GENOTYPE_SIZE
from hexapod_gait.parameters import OMNI_GENOTYPE_SIZE, OMNI_MAPPING_VERSION
from hexapod_util.files import atomic_write_bytes
from hexapod_util.npz import float_array, json_array, read_npz, UnreadableFile
import numpy as np

FORMAT = 'hexapod-archive'
FORMAT_VERSION = 1
DESCRIPTOR_DIM = 6  # a gait map's (thesis 4.2.1)


@dataclass(frozen=True)
class MapKind:
    """What an archive's rows mean: its descriptor space and its genotype mapping."""

    name: str
    descriptor_dim: int
    genotype_mapping: str
    genotype_size: int
    fitness: str  # what the fitness measures, for people


#: The kinds of map; an archive without ``kind`` in its metadata is a gait map.
MAP_KINDS: dict[str, MapKind] = {
    'gait': MapKind(
        'gait',
        DESCRIPTOR_DIM,
        GENOTYPE_MAPPING_VERSION,
        GENOTYPE_SIZE,
        'metres walked along the walking direction',
    ),
    'navigation': MapKind(
        'navigation', 2, OMNI_MAPPING_VERSION, OMNI_GENOTYPE_SIZE, 'minus the heading change [rad]'
    ),
}


def map_kind(name: Any) -> MapKind:
    """Return the kind an archive names; ArchiveError lists the known ones."""
    kind = MAP_KINDS.get(name) if isinstance(name, str) else None
    if kind is None:
        raise ArchiveError(f'unknown map kind {name!r}; known: {", ".join(MAP_KINDS)}')
    return kind


TOOL_VERSION = 'hexapod_adapt 0.1.0'
_ARRAYS = ('centroids', 'fitness', 'descriptors', 'genotypes')


class ArchiveError(ValueError):
    """An archive file or its contents is unusable; the message says which file and why."""


def centroid_hash(centroids: np.ndarray) -> str:
    """sha256 of the centroids as little-endian float64 (identifies a CVT)."""
    return hashlib.sha256(np.ascontiguousarray(centroids, dtype='<f8').tobytes()).hexdigest()


class InsertStatus(enum.Enum):
    """What :meth:`Archive.insert` did with a result."""

    NEW = 'new'  # the niche was empty: the result is its first elite
    IMPROVED = 'improved'  # the result beat the niche's elite and replaced it
    NOT_IMPROVED = 'not_improved'  # the niche's elite is at least as good: nothing changed


@dataclass(frozen=True)
class ArchiveStats:
    """Summary figures of an archive (fitness in metres over the trial duration)."""

    filled: int
    coverage: float  # filled / niches
    max: float  # noqa: A003 (the statistic; NaN when empty)
    mean: float
    median: float
    p5: float  # 5th percentile
    qd_score: float  # sum of the elites' fitness clipped at 0: never decreases as the map improves


@dataclass
class Archive:
    """A behaviour-performance map in memory: one row per niche (see the module docstring)."""

    centroids: np.ndarray
    fitness: np.ndarray
    descriptors: np.ndarray
    genotypes: np.ndarray
    metadata: dict[str, Any] = field(default_factory=dict)
    peak_tilt: np.ndarray | None = None  # (n,) [rad]; None: not recorded (all NaN)

    def __post_init__(self) -> None:
        self.centroids = np.asarray(self.centroids, dtype=float)
        self.fitness = np.asarray(self.fitness, dtype=float)
        self.descriptors = np.asarray(self.descriptors, dtype=float)
        self.genotypes = np.asarray(self.genotypes, dtype=float)
        if self.peak_tilt is None:
            self.peak_tilt = np.full(len(self.fitness), np.nan)
        self.peak_tilt = np.asarray(self.peak_tilt, dtype=float)
        kind = map_kind(self.metadata.get('kind', 'gait'))
        _check_arrays(self.centroids, self.fitness, self.descriptors, self.genotypes, kind)
        _check_tilt(self.peak_tilt, len(self.centroids), 'archive')
        self.metadata.setdefault('format', FORMAT)
        self.metadata.setdefault('format_version', FORMAT_VERSION)
        self.metadata['niches'] = int(len(self.centroids))
        self.metadata['centroid_hash'] = centroid_hash(self.centroids)
        self.metadata.setdefault('genotype_mapping', kind.genotype_mapping)
        self.metadata.setdefault('trial_duration', 5.0)

    @classmethod
    def empty(cls, centroids: np.ndarray, metadata: Mapping[str, Any] | None = None) -> 'Archive':
        """Return an archive with these centroids and no elite (its kind from ``metadata``)."""
        n = len(centroids)
        meta = dict(metadata or {})
        kind = map_kind(meta.get('kind', 'gait'))
        return cls(
            np.asarray(centroids, dtype=float),
            np.full(n, np.nan),
            np.full((n, kind.descriptor_dim), np.nan),
            np.full((n, kind.genotype_size), np.nan),
            meta,
        )

    @property
    def kind(self) -> MapKind:
        """Return what the rows mean (metadata ``kind``; a gait map if it does not say)."""
        return map_kind(self.metadata.get('kind', 'gait'))

    # -- views ------------------------------------------------------------------------------
    @property
    def n_niches(self) -> int:
        """Return the number of niches (CVT centroids)."""
        return len(self.centroids)

    @property
    def filled(self) -> np.ndarray:
        """Boolean mask of niches holding an elite."""
        return ~np.isnan(self.fitness)

    @property
    def n_filled(self) -> int:
        """Return the number of niches holding an elite."""
        return int(self.filled.sum())

    @property
    def trial_duration(self) -> float:
        """Seconds the fitness was measured over (metadata ``trial_duration``)."""
        return float(self.metadata['trial_duration'])

    def speeds(self) -> np.ndarray:
        """Fitness as average speed [m/s] (NaN for empty niches)."""
        return self.fitness / self.trial_duration

    def elite_indices(self) -> np.ndarray:
        """Return the indices of the filled niches, ascending."""
        return np.flatnonzero(self.filled)

    def only(self, niches: Sequence[int] | np.ndarray) -> 'Archive':
        """Return a copy holding only the elites of ``niches`` (the others empty): a small map."""
        keep = np.asarray(niches, dtype=int)
        if keep.size and not self.filled[keep].all():
            empty = [int(n) for n in keep if not self.filled[n]]
            raise ValueError(f'niches {empty[:5]} hold no elite')
        fitness, tilt = np.full(self.n_niches, np.nan), np.full(self.n_niches, np.nan)
        fitness[keep], tilt[keep] = self.fitness[keep], self.peak_tilt[keep]
        return Archive(
            self.centroids,
            fitness,
            self.descriptors.copy(),
            self.genotypes.copy(),
            dict(self.metadata),
            tilt,
        )

    def stats(self) -> ArchiveStats:
        """Summarise: filled niches, coverage, max/mean/median/5th-percentile fitness, QD-score."""
        f = self.fitness[self.filled]
        if f.size == 0:
            nan = float('nan')
            return ArchiveStats(0, 0.0, nan, nan, nan, nan, 0.0)
        return ArchiveStats(
            int(f.size),
            f.size / self.n_niches,
            float(f.max()),
            float(f.mean()),
            float(np.median(f)),
            float(np.percentile(f, 5)),
            float(np.sum(np.maximum(f, 0.0))),
        )

    def insert(
        self,
        niche: int,
        fitness: float,
        descriptor: np.ndarray,
        genotype: np.ndarray,
        peak_tilt: float = math.nan,
    ) -> InsertStatus:
        """
        Offer a result to ``niche`` (its peak tilt [rad], NaN if not recorded).

        It becomes the elite if the niche is empty or it is fitter (a tie keeps the incumbent).
        Returns what happened.
        """
        if np.isnan(self.fitness[niche]):
            status = InsertStatus.NEW
        elif fitness > self.fitness[niche]:
            status = InsertStatus.IMPROVED
        else:
            return InsertStatus.NOT_IMPROVED
        self.fitness[niche] = fitness
        self.descriptors[niche] = descriptor
        self.genotypes[niche] = genotype
        assert self.peak_tilt is not None  # __post_init__ made it
        self.peak_tilt[niche] = peak_tilt
        return status

    # -- files ------------------------------------------------------------------------------
    def save(
        self, path: str | os.PathLike, extra_arrays: Mapping[str, np.ndarray] | None = None
    ) -> Path:
        """
        Write atomically (temp file + fsync + rename); returns the path.

        ``extra_arrays`` are stored beside the archive's (a map-generation checkpoint's candidates
        in flight).
        """
        path = Path(path)
        meta = dict(self.metadata)
        meta['niches'], meta['centroid_hash'] = self.n_niches, centroid_hash(self.centroids)
        meta.setdefault(
            'created', _dt.datetime.now(_dt.timezone.utc).isoformat(timespec='seconds')
        )
        meta.setdefault('tool_version', TOOL_VERSION)
        self.metadata = meta
        buf = io.BytesIO()
        np.savez(
            buf,
            centroids=self.centroids,
            fitness=self.fitness,
            descriptors=self.descriptors,
            genotypes=self.genotypes,
            peak_tilt=self.peak_tilt,
            metadata=np.array(json.dumps(meta, sort_keys=True)),
            **dict(extra_arrays or {}),
        )
        atomic_write_bytes(path, buf.getvalue())
        return path


def _check_arrays(
    centroids: np.ndarray,
    fitness: np.ndarray,
    descriptors: np.ndarray,
    genotypes: np.ndarray,
    kind: MapKind,
    where: str = 'archive',
) -> None:
    dim = kind.descriptor_dim
    if centroids.ndim != 2 or centroids.shape[1] != dim or len(centroids) == 0:
        raise ArchiveError(
            f'{where}: centroids of a {kind.name} map must be (n, {dim}) with n >= 1, got'
            f' {centroids.shape}'
        )
    n = len(centroids)
    for name, arr, shape in (
        ('fitness', fitness, (n,)),
        ('descriptors', descriptors, (n, dim)),
        ('genotypes', genotypes, (n, kind.genotype_size)),
    ):
        if arr.shape != shape:
            raise ArchiveError(
                f'{where}: {name} must have shape {shape} (one row per niche), got {arr.shape}'
            )
    if not np.all(np.isfinite(centroids)):
        raise ArchiveError(f'{where}: centroids contain NaN or infinity')
    filled = ~np.isnan(fitness)
    if np.any(np.isinf(fitness)):
        raise ArchiveError(f'{where}: fitness contains infinity')
    for name, arr in (('descriptors', descriptors), ('genotypes', genotypes)):
        rows = arr[filled]
        if not np.all(np.isfinite(rows)):
            bad = int(
                np.flatnonzero(filled)[np.flatnonzero(~np.all(np.isfinite(rows), axis=1))[0]]
            )
            raise ArchiveError(f'{where}: niche {bad} has a fitness but its {name} are not finite')
        if rows.size and (rows.min() < 0.0 or rows.max() > 1.0):
            raise ArchiveError(
                f'{where}: {name} of filled niches must lie in [0, 1], '
                f'found [{rows.min():.6g}, {rows.max():.6g}]'
            )


def _check_tilt(peak_tilt: np.ndarray, n: int, where: str) -> None:
    if peak_tilt.shape != (n,):
        raise ArchiveError(
            f'{where}: peak_tilt must have shape ({n},) (one per niche), got {peak_tilt.shape}'
        )
    recorded = peak_tilt[~np.isnan(peak_tilt)]
    if recorded.size and not (np.all(np.isfinite(recorded)) and 0.0 <= recorded.min()):
        raise ArchiveError(f'{where}: peak_tilt must be NaN or finite and >= 0 rad')
    if recorded.size and recorded.max() > math.pi:
        raise ArchiveError(
            f'{where}: peak_tilt must be at most pi rad, found {recorded.max():.6g}'
        )


#: Longest trial an archive may be measured over [s] (thesis 4.1.1 uses 5 s).
MAX_TRIAL_DURATION = 120.0


def check_metadata(meta: Any, where: str) -> dict[str, Any]:
    """Return the metadata record if it is usable; ArchiveError names the first problem."""
    if not isinstance(meta, dict) or meta.get('format') != FORMAT:
        found = meta.get('format') if isinstance(meta, dict) else type(meta).__name__
        raise ArchiveError(f'{where}: not a hexapod archive (metadata format {found!r})')
    if meta.get('format_version') != FORMAT_VERSION:
        raise ArchiveError(
            f'{where}: archive format version {meta.get("format_version")!r}; this tool reads '
            f'version {FORMAT_VERSION}'
        )
    duration = meta.get('trial_duration', 5.0)
    if (
        isinstance(duration, bool)
        or not isinstance(duration, (int, float))
        or not math.isfinite(duration)
        or not 0.0 < duration <= MAX_TRIAL_DURATION
    ):
        raise ArchiveError(
            f'{where}: metadata trial_duration must be a number of seconds in '
            f'(0, {MAX_TRIAL_DURATION:g}], got {duration!r}'
        )
    evaluations = meta.get('evaluations', 0)
    if isinstance(evaluations, bool) or not isinstance(evaluations, int) or evaluations < 0:
        raise ArchiveError(
            f'{where}: metadata evaluations must be a whole number >= 0, got {evaluations!r}'
        )
    return meta


def load_archive(path: str | os.PathLike) -> Archive:
    """
    Read an archive.

    Every way the file can be bad is an ArchiveError that names the file and the problem
    (truncated, bit-flipped, foreign, altered, nonsensical metadata).
    """
    path = Path(path)
    if not path.is_file():
        raise ArchiveError(f'{path}: no such archive file')
    try:
        data = read_npz(path, (), optional=(*_ARRAYS, 'peak_tilt', 'metadata'))
        missing = [k for k in (*_ARRAYS, 'metadata') if k not in data]
        if missing:
            raise ArchiveError(f'{path}: not a hexapod archive (missing {", ".join(missing)})')
        arrays = {name: float_array(data[name], f'{path}: {name}') for name in _ARRAYS}
        tilt = (
            float_array(data['peak_tilt'], f'{path}: peak_tilt') if 'peak_tilt' in data else None
        )
        meta = json_array(data['metadata'], f'{path}: metadata')
    except (OSError, UnreadableFile) as exc:
        raise ArchiveError(str(exc)) from None
    meta = check_metadata(meta, str(path))
    try:
        kind = map_kind(meta.get('kind', 'gait'))
    except ArchiveError as exc:
        raise ArchiveError(f'{path}: {exc}') from None
    if meta.get('genotype_mapping', kind.genotype_mapping) != kind.genotype_mapping:
        raise ArchiveError(
            f'{path}: a {kind.name} map holds {kind.genotype_mapping} genotypes, not'
            f' {meta.get("genotype_mapping")!r}'
        )
    _check_arrays(
        arrays['centroids'],
        arrays['fitness'],
        arrays['descriptors'],
        arrays['genotypes'],
        kind,
        where=str(path),
    )
    if meta.get('centroid_hash') != centroid_hash(arrays['centroids']):
        raise ArchiveError(
            f'{path}: centroids do not match the centroid hash in the metadata (file altered?)'
        )
    if tilt is not None:
        _check_tilt(tilt, len(arrays['centroids']), str(path))
    return Archive(
        arrays['centroids'],
        arrays['fitness'],
        arrays['descriptors'],
        arrays['genotypes'],
        meta,
        tilt,
    )


def compatibility_problems(archive: Archive, expected: Mapping[str, Any]) -> list[str]:
    """
    List, as readable sentences, the metadata entries that differ from ``expected``.

    Empty if compatible. Keys compared: any of ``expected``'s keys present in it.
    """
    problems = []
    for key, want in expected.items():
        have = archive.metadata.get(key)
        if have != want:
            problems.append(f'{key} is {have!r} in the archive but {want!r} here')
    return problems


# -- thesis / pymap_elites text files -----------------------------------------------------------
def load_centroids(path: str | os.PathLike, dim: int = DESCRIPTOR_DIM) -> np.ndarray:
    """Return a ``centroids_<n>_<dim>.dat`` file: one centroid per row, whitespace separated."""
    path = Path(path)
    try:
        c = np.loadtxt(path, ndmin=2)
    except (OSError, ValueError) as exc:
        raise ArchiveError(f'{path}: cannot read centroids ({exc})') from exc
    if c.shape[1] != dim:
        raise ArchiveError(f'{path}: centroids must have {dim} columns, got {c.shape[1]}')
    return c


def save_centroids(path: str | os.PathLike, centroids: np.ndarray) -> None:
    """Write centroids as a ``centroids_<n>_<dim>.dat`` text file, atomically."""
    buf = io.StringIO()
    np.savetxt(buf, centroids, fmt='%.17g')
    atomic_write_bytes(path, buf.getvalue().encode())


def import_thesis_map(
    path: str | os.PathLike,
    centroids: np.ndarray | None = None,
    metadata: Mapping[str, Any] | None = None,
) -> Archive:
    """
    Read a thesis/pymap_elites map (``archive_<n>.dat``).

    Rows of fitness, descriptor (6), centroid (6), genotype (32). With ``centroids`` (e.g. from
    :func:`load_centroids`) rows are placed in the niche whose centroid is nearest to the row's;
    without, the rows' centroids are the niches. Fitness is taken as metres in 5 s, as the thesis
    code computed it.
    """
    path = Path(path)
    width = 1 + 2 * DESCRIPTOR_DIM + GENOTYPE_SIZE
    try:
        rows = np.loadtxt(path, ndmin=2)
    except (OSError, ValueError) as exc:
        raise ArchiveError(f'{path}: cannot read a thesis map ({exc})') from exc
    if rows.size == 0:
        raise ArchiveError(f'{path}: the map has no rows')
    if rows.shape[1] != width:
        raise ArchiveError(
            f'{path}: a thesis map row has {width} numbers (fitness, 6 descriptor, 6 centroid, '
            f'{GENOTYPE_SIZE} genes); found {rows.shape[1]}'
        )
    fit, desc = rows[:, 0], rows[:, 1:7]
    cent, genes = rows[:, 7:13], rows[:, 13:]
    meta = {'source': f'thesis map {path.name}', 'evaluations': None, 'seed': None}
    meta.update(metadata or {})
    if centroids is None:
        return Archive(cent, fit, desc, genes, meta)
    from scipy.spatial import cKDTree

    archive = Archive.empty(centroids, meta)
    dist, idx = cKDTree(archive.centroids).query(cent)
    if np.max(dist) > 1e-6:
        raise ArchiveError(
            f"{path}: row {int(np.argmax(dist))}'s centroid is {np.max(dist):.3g} from every "
            'centroid in the given CVT (a different centroids file?)'
        )
    if len(np.unique(idx)) != len(idx):
        raise ArchiveError(f'{path}: two rows claim the same niche')
    archive.fitness[idx], archive.descriptors[idx], archive.genotypes[idx] = fit, desc, genes
    _check_arrays(
        archive.centroids,
        archive.fitness,
        archive.descriptors,
        archive.genotypes,
        archive.kind,
        where=str(path),
    )
    return archive


def export_thesis_map(archive: Archive, path: str | os.PathLike) -> None:
    """Write the filled niches in the thesis/pymap_elites text format (atomically)."""
    idx = archive.elite_indices()
    rows = np.hstack(
        [
            archive.fitness[idx, None],
            archive.descriptors[idx],
            archive.centroids[idx],
            archive.genotypes[idx],
        ]
    )
    buf = io.StringIO()
    np.savetxt(buf, rows, fmt='%.17g')
    atomic_write_bytes(path, buf.getvalue().encode())
