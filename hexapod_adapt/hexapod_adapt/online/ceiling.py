# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
What a map holds under a damage: every one of its gaits evaluated with that damage applied.

The best of them is the ceiling an adaptation run under that damage is measured against (regret:
adapted speed / ceiling speed). Evaluations are as in adaptation: the trial engine, collisions
not fatal, the map's trial duration. A ceiling costs one evaluation per gait (about 3 min of one
core per damage case for the default map on MuJoCo), so each is cached in its own file, keyed by
what it depends on: the map's gaits, the engine and its settings, the URDF, the gait mapping,
the trial duration and the damage (:func:`ceiling_key`). A cached file is checked against its
key when read; a damaged or foreign one is recomputed, never trusted.

A case being walked keeps the gaits walked so far beside the cache (:class:`WalkingFile`, every
minute): a run stopped mid-case goes on from there.

A finished cache can be packed (:func:`pack_ceilings`): its files go, unchanged, into a few zip
files of the same folder (``ceilings_<engine>_<kind>_<n>.zip``), so a shipped cache of hundreds
of cases is a few dozen files. Loose files are read before packs.

Cache them with ``python -m hexapod_adapt.online.ceilings_cli`` (``maps/make_ceilings.sh``).
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, replace
import hashlib
import io
import json
import os
from pathlib import Path
import time
from typing import Callable, Iterable, Iterator, Sequence
import zipfile
import zlib

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.mapping.simulation import (
    trial_substeps,
    trial_walk_key,
    worker_simulator,
)
from hexapod_sim import evaluate_gaits, EvaluationResult
from hexapod_sim.damage import as_damage, Damage, LegDamage
from hexapod_sim.evaluation import EVALUATION_VERSION
from hexapod_sim.simulator import start_key
from hexapod_util.files import atomic_write_bytes
from hexapod_util.npz import (
    float_array,
    json_array,
    read_npz,
    read_npz_bytes,
    UnreadableFile,
)
from hexapod_util.processes import map_in_workers, Stopped
import numpy as np

FORMAT = 'hexapod-ceiling/v1'
#: A partial ceiling walks only this share of the map, its fastest gaits intact: on the map of
#: 2026-11-28 every one of the 168 cases' fastest damaged gait was among the intact-fastest 20 %
#: (hexapod_adapt/maps/ceilings/README.md, "Partial ceilings"). make_ceilings.sh makes the kinds
#: beyond lifted legs partial.
TOP_FRACTION = 0.4
#: Gaits a re-score made while a run waits walks before the run goes on, the map's fastest
#: intact: the streaming prior's before the first trial, and a blind run's when it names a damage
#: not cached (:func:`quick_rescore`; ``adapt_prior_first_trial_s`` in docs/benchmarks.md).
TOP_FIRST = 256
#: Gaits :func:`quick_rescore` walks between two looks at its ``stop``: about a second's work.
QUICK_CHUNK = 8
#: Cached ceilings per pack: the default map's (about 130 kB each) keep a pack under 1 MB.
PACK_MEMBERS = 6
#: How a damaged pack reads (zipfile and zlib raise these on bad bytes).
_BAD_PACK = (OSError, EOFError, ValueError, NotImplementedError, zipfile.BadZipFile, zlib.error)


@dataclass(frozen=True)
class Ceiling:
    """Every elite of a map evaluated under one damage."""

    damage: Damage
    engine: str
    niches: np.ndarray  # (n,) archive niche of each elite
    # (n,) m/s along the walking direction, with the damage: walked, or for a gait a partial
    # ceiling did not walk, its estimate (:func:`estimate_unwalked`)
    speeds: np.ndarray
    walked: np.ndarray | None = None  # (n,) bool: walked under the damage (None: every gait)

    @property
    def failed_legs(self) -> tuple[int, ...]:
        """Return the damaged legs' numbers."""
        return self.damage.failed_legs

    @property
    def walked_mask(self) -> np.ndarray:
        """Return which gaits were walked under the damage (all of a full ceiling)."""
        return np.ones(len(self.speeds), bool) if self.walked is None else self.walked

    @property
    def walked_speeds(self) -> np.ndarray:
        """Return the speeds, -inf for a gait not walked (for argmax-like choices)."""
        return np.where(self.walked_mask, self.speeds, -np.inf)

    @property
    def best_index(self) -> int:
        """Position (in ``niches``) of the fastest gait walked under the damage."""
        return int(np.argmax(self.walked_speeds))

    @property
    def best_speed(self) -> float:
        """Return the ceiling: the fastest any gait of the map walks with the damage [m/s]."""
        return float(self.speeds[self.best_index])

    @property
    def best_niche(self) -> int:
        """Niche of the fastest gait under the damage."""
        return int(self.niches[self.best_index])

    def beating(self, speed: float) -> int:
        """How many gaits walked faster than ``speed`` [m/s] with the damage (of those walked)."""
        return int(np.sum(self.walked_speeds > speed))


def estimate_unwalked(intact: np.ndarray, speeds: np.ndarray) -> np.ndarray:
    """
    Return ``speeds`` (NaN: not walked under the damage) with each gait not walked estimated.

    Such a gait gets its ``intact`` speed times the median ratio of damaged to intact speed over
    the gaits walked (1 before any): M-BOA's prior mean for it, in a partial ceiling or a
    re-score still streaming.
    """
    speeds = np.array(speeds, dtype=float)
    missing = np.isnan(speeds)
    if missing.any():
        done = ~missing & (intact > 1e-6)
        ratio = float(np.median(speeds[done] / intact[done])) if done.any() else 1.0
        speeds[missing] = intact[missing] * ratio
    return speeds


class RescoreStopped(Exception):
    """A re-score was stopped before it ended (its ``stop()`` held): nothing of it is kept."""


def quick_rescore(
    archive: Archive,
    damage: Damage,
    engine: str,
    first: int = TOP_FIRST,
    stop: Callable[[], bool] | None = None,
    workers: int = 1,
) -> np.ndarray:
    """
    Return the map's speeds under ``damage``: its ``first`` intact-fastest gaits walked now.

    The rest are estimated (:func:`estimate_unwalked`); in the order of
    ``archive.elite_indices()``. About 0.1 s of one core a gait on MuJoCo; nothing is cached.
    ``stop()``, asked before each :data:`QUICK_CHUNK` gaits (with ``workers`` > 1: while each is
    awaited, :func:`map_in_workers`), ends it early with :class:`RescoreStopped` (a cancel need
    not wait for the whole re-score). ``workers`` > 1 walks them in that many processes, to the
    same speeds.
    """
    niches = archive.elite_indices()
    intact = archive.speeds()[niches]
    top = intact_order(archive)[: max(1, first)]
    speeds = np.full(len(niches), np.nan)
    how = Rescoring.of(archive, damage, engine)
    parts = np.array_split(top, range(QUICK_CHUNK, len(top), QUICK_CHUNK))
    jobs = [(how, archive.genotypes[niches[part]]) for part in parts]
    try:
        # the walks first: zip then runs them to their end, and the pool shuts down cleanly
        for walked, part in zip(map_in_workers(evaluate_part, jobs, workers, stop), parts):
            speeds[part] = walked
    except Stopped:
        raise RescoreStopped(f'the re-score under {damage.label} was stopped') from None
    return estimate_unwalked(intact, speeds)


def intact_order(archive: Archive, niches: np.ndarray | None = None) -> np.ndarray:
    """Return positions in ``niches`` (default: the elites) from the fastest intact gait down."""
    niches = archive.elite_indices() if niches is None else niches
    return np.argsort(-archive.speeds()[niches], kind='stable')


def partial_share(archive: Archive, niches: np.ndarray | None = None) -> np.ndarray:
    """Return the positions in ``niches`` partial ceilings walk, sorted (:data:`TOP_FRACTION`)."""
    order = intact_order(archive, niches)
    return np.sort(order[: int(np.ceil(TOP_FRACTION * len(order)))])


def deepest_share(archive: Archive, ceilings: Iterable[Ceiling]) -> float:
    """
    Return how deep in the map's intact order the fastest damaged gait of any full ceiling lies.

    The share of the map's gaits, intact-fastest first, a partial ceiling must walk to hold each
    of them (0 if none is full): :data:`TOP_FRACTION` is meant to be more.
    """
    order = intact_order(archive)
    rank = np.empty(len(order), int)
    rank[order] = np.arange(len(order))
    full = [c for c in ceilings if c.walked is None]
    return max(((rank[c.best_index] + 1) / len(order) for c in full), default=0.0)


def _estimated(archive: Archive, c: Ceiling | None) -> Ceiling | None:
    """Return ``c`` with its gaits not walked estimated from the map (as read: NaN)."""
    if c is None or c.walked is None:
        return c
    return replace(c, speeds=estimate_unwalked(archive.speeds()[c.niches], c.speeds))


def map_digest(archive: Archive) -> str:
    """SHA-256 of what a ceiling depends on in a map: its elites' niches and genotypes."""
    niches = archive.elite_indices()
    h = hashlib.sha256()
    h.update(np.ascontiguousarray(niches, dtype='<i8').tobytes())
    h.update(np.ascontiguousarray(archive.genotypes[niches], dtype='<f8').tobytes())
    return h.hexdigest()


def ceiling_key(
    archive: Archive, damage: Damage | Sequence[int], engine: str, partial: bool = False
) -> dict:
    """
    Return everything a ceiling depends on (its cache key, stored in the file).

    A thesis damage (lifted legs) is keyed by its legs alone, as before other damage types
    existed, so the shipped cache stays valid; any other damage adds its description; a partial
    ceiling (``partial``: the intact-fastest :data:`TOP_FRACTION` walked), its share.
    """
    damage = as_damage(damage)
    # at the physics steps it is computed at: the map's on its own engine, else converged
    key = {
        'format': FORMAT,
        'map_sha256': map_digest(archive),
        **trial_walk_key(archive, engine),
        'failed_legs': list(damage.failed_legs),
        'collisions_fatal': False,
        'evaluation_version': EVALUATION_VERSION,  # a cache made under other rules is not reused
    }
    if not damage.thesis:
        # an unpowered leg's dead joints follow (keys of the other kinds are as before)
        key['damage'] = [[d.leg, d.kind, d.strength, *d.joints] for d in damage.legs]
        key.update(start_key([damage]))  # a locked leg's start (cases made before it: stale)
    if partial:
        key['top_fraction'] = TOP_FRACTION
    return key


def _damage_of(key: dict) -> Damage:
    if 'damage' not in key:
        return Damage.lifted(key['failed_legs'])
    return Damage(
        tuple(
            LegDamage(leg, kind, strength, tuple(joints))
            for leg, kind, strength, *joints in key['damage']
        )
    )


def cache_path(directory: str | os.PathLike, key: dict) -> Path:
    """Return the file a ceiling with ``key`` is cached in."""
    digest = hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()[:16]
    legs = ''.join(map(str, key['failed_legs'])) or 'intact'
    kinds = ''.join(
        f'_{leg}{kind}' + ''.join(f'-{j}' for j in joints)
        for leg, kind, _, *joints in key.get('damage', [])
    )
    subset = f'_top{key["subset"]["top"]}' if 'subset' in key else ''
    subset += f'_part{round(100 * key["top_fraction"])}' if 'top_fraction' in key else ''
    return Path(directory) / f'ceiling_{key["engine"]}_legs{legs}{kinds}{subset}_{digest}.npz'


@dataclass(frozen=True)
class Rescoring:
    """How a map's gaits are walked under a damage (a pool job's settings)."""

    engine: str
    substeps: int  # physics steps per row: the map's on its own engine, else converged
    damage: Damage
    duration: float  # [s] the map's trial

    @classmethod
    def of(cls, archive: Archive, damage: Damage | Sequence[int], engine: str) -> 'Rescoring':
        """Return how ``archive``'s gaits are walked under ``damage`` on ``engine``."""
        return cls(
            engine, trial_substeps(archive, engine), as_damage(damage), archive.trial_duration
        )


def _walk(how: Rescoring, genes: np.ndarray, record_tilt: bool = False) -> list[EvaluationResult]:
    """Walk some gaits as a ceiling walks them: one EvaluationResult each."""
    return evaluate_gaits(
        list(genes),
        worker_simulator(how.engine, how.substeps),
        duration=how.duration,
        collisions_fatal=False,
        failed_legs=how.damage,
        record_tilt=record_tilt,
    )


def evaluate_part(args: tuple[Rescoring, np.ndarray]) -> np.ndarray:
    """Return the speeds of some gaits ``(how, genotypes)`` (a pool job)."""
    how, genes = args
    return np.array([r.speed for r in _walk(how, genes)])


def evaluate_tilts(how: Rescoring, genes: np.ndarray) -> np.ndarray:
    """Return how far each gait tilts the body as it walks, as a ceiling walks it [rad]."""
    return np.array([r.peak_tilt for r in _walk(how, genes, record_tilt=True)])


@dataclass(frozen=True)
class WalkingFile:
    """
    Where a ceiling being walked keeps its chunks walked so far, so a stopped run goes on.

    Next to the cached file, named ``walking_<its name>``; it holds the ceiling's key, so a file
    for another map, damage or engine is never taken up. A damaged one is walked again.
    """

    path: Path
    key: dict
    every: float = 60.0  # [s] between two keeps

    @classmethod
    def beside(cls, cached: Path, key: dict) -> 'WalkingFile':
        """Return the walking file of the ceiling cached at ``cached`` under ``key``."""
        return cls(cached.with_name(f'walking_{cached.name}'), key)

    def taken_up(self, chunk: int, total: int) -> list[np.ndarray]:
        """Return the chunks already walked (none if the file is absent, foreign or damaged)."""
        try:
            data = read_npz(self.path, ('key', 'chunk', 'speeds'))
            stored = json_array(data['key'], f'{self.path}: the key')
            speeds = float_array(data['speeds'], f'{self.path}: speeds')
            stored_chunk = int(data['chunk'])
        except (OSError, UnreadableFile, TypeError, ValueError):
            return []
        if stored != self.key or stored_chunk != chunk or speeds.ndim != 1:
            return []
        whole = len(speeds) == total or (len(speeds) < total and len(speeds) % chunk == 0)
        if not whole or not np.isfinite(speeds).all():
            return []
        return np.split(speeds, range(chunk, len(speeds), chunk)) if len(speeds) else []

    def keep(self, chunk: int, parts: list[np.ndarray]) -> None:
        """Keep the chunks walked so far (atomically)."""
        buf = io.BytesIO()
        np.savez(
            buf,
            key=np.array(json.dumps(self.key, sort_keys=True)),
            chunk=np.array(chunk),
            speeds=np.concatenate(parts) if parts else np.zeros(0),
        )
        atomic_write_bytes(self.path, buf.getvalue())

    def drop(self) -> None:
        """Remove the file (the ceiling is cached)."""
        self.path.unlink(missing_ok=True)


def compute_ceiling(
    archive: Archive,
    damage: Damage | Sequence[int],
    engine: str,
    workers: int = 1,
    chunk: int = 64,
    progress: Callable[[int, int], None] | None = None,
    niches: np.ndarray | None = None,
    partial: bool = False,
    walking: WalkingFile | None = None,
) -> Ceiling:
    """
    Evaluate every elite of ``archive`` (or only ``niches``) with ``damage`` on ``engine``.

    ``partial``: only the intact-fastest :data:`TOP_FRACTION` of them; the others are estimated
    (:func:`estimate_unwalked`). No cache. ``progress(done, total)`` is called after each chunk
    of ``chunk`` gaits. ``walking``: the chunks walked so far are kept there and taken up again.
    """
    damage = as_damage(damage)
    niches = archive.elite_indices() if niches is None else np.asarray(niches, dtype=int)
    walk = np.arange(len(niches))
    if partial:
        walk = partial_share(archive, niches)
    genes = archive.genotypes[niches[walk]]
    how = Rescoring.of(archive, damage, engine)
    jobs = [(how, part) for part in np.split(genes, range(chunk, len(genes), chunk)) if len(part)]
    parts: list[np.ndarray] = walking.taken_up(chunk, len(genes)) if walking is not None else []
    last_kept = time.monotonic()

    def collect(results: Iterable[np.ndarray]) -> None:
        nonlocal last_kept
        for part in results:
            parts.append(part)
            if progress is not None:
                progress(sum(len(x) for x in parts), len(genes))
            if walking is not None and time.monotonic() - last_kept >= walking.every:
                walking.keep(chunk, parts)
                last_kept = time.monotonic()

    collect(map_in_workers(evaluate_part, jobs[len(parts) :], workers))  # noqa: E203
    speeds = np.full(len(niches), np.nan)
    speeds[walk] = np.concatenate(parts) if parts else np.zeros(0)
    if not partial:
        return Ceiling(damage, engine, niches, speeds)
    walked = np.zeros(len(niches), bool)
    walked[walk] = True
    intact = archive.speeds()[niches]
    return Ceiling(damage, engine, niches, estimate_unwalked(intact, speeds), walked)


def _read(path: Path, key: dict) -> Ceiling | None:
    """Return the cached ceiling at ``path`` if it is one for ``key`` (None if absent or not)."""
    try:
        data = read_npz(path, ('key', 'niches', 'speeds'))
    except (OSError, UnreadableFile):  # absent or damaged: computed again and rewritten
        return None
    return _checked(data, str(path), key)


def _checked(data: dict[str, np.ndarray], where: str, key: dict) -> Ceiling | None:
    try:
        stored = json_array(data['key'], f'{where}: the key')
        niches, speeds = data['niches'], float_array(data['speeds'], f'{where}: speeds')
    except UnreadableFile:
        return None
    walked = np.isfinite(speeds)
    if 'top_fraction' in key:  # a partial ceiling: NaN for a gait not walked
        ok = walked.any() and not np.isinf(speeds).any()
    else:
        ok = walked.all()
    if stored != key or niches.shape != speeds.shape or not ok:
        return None
    return Ceiling(
        _damage_of(key), key['engine'], niches, speeds, walked if 'top_fraction' in key else None
    )


def _packs(directory: Path) -> Iterator[tuple[Path, list[str]]]:
    """Yield each readable pack of ``directory``, in name order, with its members' names."""
    for pack in sorted(directory.glob('ceilings_*.zip')):
        try:
            with zipfile.ZipFile(pack) as packed:
                members = packed.namelist()
        except _BAD_PACK:  # a damaged pack holds nothing to trust
            continue
        yield pack, members


def _cached_in(directory: str | os.PathLike, key: dict) -> Ceiling | None:
    """Return the ceiling for ``key`` that ``directory`` holds, loose or packed, or None."""
    path = cache_path(directory, key)
    cached = _read(path, key)
    if cached is not None:
        return cached
    for pack, members in _packs(Path(directory)):
        if path.name not in members:
            continue
        try:
            with zipfile.ZipFile(pack) as packed:
                raw = packed.read(path.name)
            data = read_npz_bytes(raw, f'{pack}:{path.name}', ('key', 'niches', 'speeds'))
        except (*_BAD_PACK, UnreadableFile):  # a damaged pack holds nothing to trust
            continue
        cached = _checked(data, f'{pack}:{path.name}', key)
        if cached is not None:
            return cached
    return None


def cached_names(directory: str | os.PathLike) -> set[str]:
    """
    Return the file names of the cases ``directory`` holds, loose or packed (no key is checked).

    A pack that cannot be read holds nothing.
    """
    directory = Path(directory)
    names = {p.name for p in directory.glob('ceiling_*.npz')}
    for _, members in _packs(directory):
        names.update(members)
    return names


def holds_ceiling(directory: str | os.PathLike, key: dict) -> bool:
    """Whether ``directory`` holds a readable ceiling for ``key``, loose or packed."""
    return _cached_in(directory, key) is not None


def _pack_group(path: Path) -> str | None:
    """Return the pack group of a cached ceiling file (engine and damage kind), None if damaged."""
    try:
        key = json_array(read_npz(path, ('key',))['key'], f'{path}: the key')
        kinds = sorted({'-'.join(map(str, [d[1], *d[3:]])) for d in key.get('damage', [])})
        return f'{key["engine"]}_{"+".join(kinds) or "lifted"}'
    except (OSError, UnreadableFile, AttributeError, IndexError, KeyError, TypeError):
        return None


def pack_ceilings(directory: str | os.PathLike, per_pack: int = PACK_MEMBERS) -> list[Path]:
    """
    Move the loose cached ceilings of ``directory`` into packs; return the packs written.

    Grouped by engine and damage kind, in name order, ``per_pack`` files to a pack; each pack is
    written atomically before its files go. Damaged files stay loose (recomputed when asked).
    """
    if per_pack < 1:
        raise ValueError(f'per_pack must be at least 1, got {per_pack}')
    directory = Path(directory)
    groups: dict[str, list[Path]] = defaultdict(list)
    for path in sorted(directory.glob('ceiling_*.npz')):
        group = _pack_group(path)
        if group is not None:
            groups[group].append(path)
    written = []
    for group, paths in groups.items():
        taken = {p.name for p in directory.glob(f'ceilings_{group}_*.zip')}
        n = 0
        for start in range(0, len(paths), per_pack):
            while f'ceilings_{group}_{n}.zip' in taken:
                n += 1
            pack = directory / f'ceilings_{group}_{n}.zip'
            taken.add(pack.name)
            members = paths[start : start + per_pack]  # noqa: E203 - ruff's slice spacing
            buf = io.BytesIO()
            with zipfile.ZipFile(buf, 'w', zipfile.ZIP_STORED) as packed:  # members: compressed
                for member in members:
                    packed.writestr(member.name, member.read_bytes())
            atomic_write_bytes(pack, buf.getvalue())
            for member in members:
                member.unlink()
            written.append(pack)
    return written


def cached_ceiling(
    archive: Archive,
    damage: Damage | Sequence[int],
    engine: str,
    dirs: Sequence[str | os.PathLike],
) -> Ceiling | None:
    """
    Return the ceiling cached in the first of ``dirs`` that holds it, or None (no compute).

    A full ceiling is looked for first, then a partial one (its gaits not walked estimated).
    """
    for partial in (False, True):
        key = ceiling_key(archive, damage, engine, partial)
        for directory in dirs:
            cached = _cached_in(directory, key)
            if cached is not None:  # the key's map digest covers the elites' niches
                return _estimated(archive, cached)
    return None


def ceiling(
    archive: Archive,
    failed_legs: Damage | Sequence[int],
    engine: str,
    cache_dir: str | os.PathLike | None = None,
    workers: int = 1,
    read_dirs: Sequence[str | os.PathLike] = (),
    progress: Callable[[int, int], None] | None = None,
    partial: bool = False,
) -> Ceiling:
    """
    Return the ceiling of ``archive`` under a damage on ``engine`` (cached if asked).

    A cached copy (full or partial) is looked for in ``read_dirs`` (e.g. the shipped, read-only
    cache), then in ``cache_dir``, where a computed one is written; ``partial``: one not cached
    is computed partial (:data:`TOP_FRACTION`).
    """
    key = ceiling_key(archive, failed_legs, engine, partial)
    path = cache_path(cache_dir, key) if cache_dir is not None else None
    dirs = [*read_dirs] + ([cache_dir] if cache_dir is not None else [])
    cached = cached_ceiling(archive, failed_legs, engine, dirs)
    if cached is not None:
        return cached
    walking = WalkingFile.beside(path, key) if path is not None else None
    result = compute_ceiling(
        archive, failed_legs, engine, workers, progress=progress, partial=partial, walking=walking
    )
    _write(path, key, result)
    if walking is not None:
        walking.drop()
    return result


def approximate_key(
    archive: Archive, damage: Damage | Sequence[int], engine: str, guide_engine: str, top: int
) -> dict:
    """Return the cache key of :func:`approximate_ceiling`'s result."""
    return {
        **ceiling_key(archive, damage, engine),
        'subset': {'top': int(top), 'guide_engine': guide_engine},
    }


def approximate_ceiling(
    archive: Archive,
    damage: Damage | Sequence[int],
    engine: str,
    guide: Ceiling,
    top: int,
    cache_dir: str | os.PathLike | None = None,
    workers: int = 1,
) -> Ceiling:
    """
    Approximate a ceiling on a slow engine: only the ``top`` gaits that walk best under ``guide``.

    ``guide`` is the same damage's ceiling on another engine (e.g. PyBullet over the 1000 gaits
    that walk best under the damage on MuJoCo). A gait outside them may walk faster: a ratio
    against this ceiling can exceed 1. Cached like a full one, under its own key.
    """
    damage = as_damage(damage)
    if guide.damage != damage:
        raise ValueError(f'the guide ceiling is for {guide.damage.label}, not {damage.label}')
    key = approximate_key(archive, damage, engine, guide.engine, top)
    path = cache_path(cache_dir, key) if cache_dir is not None else None
    if path is not None:
        cached = _read(path, key)
        if cached is not None:
            return cached
    niches = guide.niches[np.argsort(-guide.walked_speeds, kind='stable')[:top]]
    result = compute_ceiling(archive, damage, engine, workers, niches=np.sort(niches))
    _write(path, key, result)
    return result


def store_ceiling(archive: Archive, result: Ceiling, cache_dir: str | os.PathLike | None) -> None:
    """Write a computed ceiling to ``cache_dir`` (atomically; nothing if None)."""
    if cache_dir is not None:
        key = ceiling_key(archive, result.damage, result.engine, result.walked is not None)
        _write(cache_path(cache_dir, key), key, result)


def _write(path: Path | None, key: dict, result: Ceiling) -> None:
    if path is not None:
        buf = io.BytesIO()
        np.savez_compressed(
            buf,
            key=np.array(json.dumps(key, sort_keys=True)),
            niches=result.niches,
            speeds=np.where(result.walked_mask, result.speeds, np.nan),  # what was walked only
        )
        atomic_write_bytes(path, buf.getvalue())
