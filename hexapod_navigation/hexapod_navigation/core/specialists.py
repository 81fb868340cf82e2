# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Gaits made for a damage, as extra navigation steps (issue 31: lifted legs walk too slowly).

The navigation repertoire's steps are omnidirectional gaits chosen on the intact robot; under a
lifted leg its best step toward a goal makes 0.07-0.23 m/s, while the default adaptation map's
fastest gait under that same damage walks 0.44-0.55 m/s in its own direction
(``studies/navigation/results/navigation_bound.txt``). The specialists are such gaits: for the
intact robot and each damage of the navigation bank of :data:`SOURCE_KINDS`, the map's fastest gait
under it (its shipped ceiling; intact, its fitness) among those that keep ``min_stance_legs`` feet
down throughout, as the repertoire's steps must. Lifted legs only by default: the gaits made for
locked legs lean on the rigid leg, and two of them tipped the robot over on dead coxas and lost
tibias (studies/navigation/README.md, thirteenth round). Each is played at its own crab angle and
the other crab angles of :data:`CRAB_OFFSETS` (every 45 deg, the reverse included), at its own
stride and the shorter ones of :data:`STRIDE_SCALES`, with each of :data:`TURN_RATES` (arcs), where
its feet can follow those paths.

They are measured like the bank (one step from rest, collisions not fatal) intact and under each of
the bank's damages, with the largest tilt each step reaches (a gait made for one damage can tip the
robot over under another: :meth:`Specialists.stable`). :func:`extend` appends them to the
repertoire and its bank: the correction and the planner then treat them as any other step. The file
is keyed like a bank (:func:`hexapod_navigation.core.step_bank.bank_key` of the specialists'
genes): one made for other damages, another engine or URDF is refused with the reason.

``python -m hexapod_navigation.offline.specialists_cli`` makes them
(``maps/make_navigation_specialists.sh``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import partial
import hashlib
import io
import json
import math
import os
from pathlib import Path
from typing import Callable, Sequence

from hexapod_adapt import Archive, cached_ceiling, gait_min_stance, map_digest, shipped_map
from hexapod_gait.parameters import from_genotype, to_omni_genotype
from hexapod_navigation.core.repertoire import PACKAGE, Repertoire
from hexapod_navigation.core.step_bank import bank_key, step_table, StepBank
from hexapod_sim.damage import Damage
from hexapod_util.files import atomic_write_bytes
from hexapod_util.npz import float_array, json_array, read_npz, UnreadableFile
from hexapod_util.processes import map_in_workers
import numpy as np

FORMAT = 'hexapod-nav-specialists/v3'  # v2: each step's end tilt; v3: its largest tilt
NAVIGATION_SPECIALISTS = 'navigation_specialists.npz'
#: rad/s: each specialist is played straight and along these arcs
TURN_RATES = (-0.5, -0.25, 0.0, 0.25, 0.5)
#: rad: ... at its own crab angle and turned by each of these (the reverse included)
CRAB_OFFSETS = tuple(k * math.pi / 4 for k in range(8))
#: ... at its own stride speed (body_velocity) and these fractions of it: a shorter stride lets
#: the feet follow crab angles the gait's own stride cannot reach
STRIDE_SCALES = (1.0, 0.75, 0.5)
#: the kinds of leg damage (:attr:`hexapod_sim.damage.LegDamage.kind`) gaits are made for
SOURCE_KINDS = ('lifted',)


@dataclass(frozen=True)
class Specialists:
    """Gaits made for a damage: ``steps[h, i]`` = one step (dx, dy, dyaw) under ``damages[h]``."""

    genotypes: np.ndarray  # (k, 34): omni genotypes
    intact: np.ndarray  # (k, 3): one step on the intact robot
    steps: np.ndarray  # (h, k, 3)
    damages: tuple[Damage, ...]
    step_duration: float
    tilt: np.ndarray  # (h, k) rad: the largest |roll| or |pitch| during the step

    def stable(self, max_tilt: float) -> Specialists:
        """Return those whose step never tilts more than ``max_tilt`` rad under any damage."""
        keep = np.all(self.tilt <= max_tilt, axis=0)
        return Specialists(
            self.genotypes[keep],
            self.intact[keep],
            self.steps[:, keep],
            self.damages,
            self.step_duration,
            self.tilt[:, keep],
        )

    def __len__(self) -> int:
        return len(self.genotypes)

    def repertoire(self, engine: str) -> Repertoire:
        """Return the specialists alone, as navigation steps (niche -1: they are in no map)."""
        return Repertoire(
            np.full(len(self), -1),
            self.intact[:, :2],
            np.abs(self.intact[:, 2]),
            self.genotypes,
            self.step_duration,
            'specialists',
            engine,
        )


def source_gaits(
    archive: Archive,
    damages: Sequence[Damage],
    engine: str,
    ceiling_dirs: Sequence[str | os.PathLike],
    min_stance_legs: int,
) -> list[int]:
    """
    Return the niches of the map's fastest gait intact and under each damage (each once).

    Only gaits with at least ``min_stance_legs`` feet down throughout count. ValueError names a
    damage whose ceiling no directory in ``ceiling_dirs`` holds.
    """
    elites = archive.elite_indices()
    stable = {
        int(n)
        for n in elites
        if gait_min_stance(from_genotype(archive.genotypes[n])) >= min_stance_legs
    }
    if not stable:
        raise ValueError(f'no gait of the map keeps {min_stance_legs} feet down throughout')
    ok = np.array([int(n) in stable for n in elites])
    niches = [int(elites[ok][np.argmax(archive.fitness[elites[ok]])])]
    for damage in damages:
        ceiling = cached_ceiling(archive, damage, engine, ceiling_dirs)
        if ceiling is None:
            raise ValueError(
                f'no ceiling of the map under {damage.label} in'
                f' {", ".join(map(str, ceiling_dirs))} (hexapod_adapt/maps/make_ceilings.sh)'
            )
        fits = np.array([int(n) in stable for n in ceiling.niches])
        niches.append(
            int(ceiling.niches[np.argmax(np.where(fits, ceiling.walked_speeds, -np.inf))])
        )
    return list(dict.fromkeys(niches))


def variants(archive: Archive, niches: Sequence[int]) -> np.ndarray:
    """
    Return each gait at every crab angle, stride and turn rate below, as omni genotypes.

    Crab angles: its own turned by each of :data:`CRAB_OFFSETS`; strides: its own times each of
    :data:`STRIDE_SCALES`; turn rates: :data:`TURN_RATES`.
    """
    out = []
    for n in niches:
        gait = from_genotype(archive.genotypes[n])
        for offset in CRAB_OFFSETS:
            angle = (gait.crab_angle + offset + math.pi) % (2 * math.pi) - math.pi
            for scale in STRIDE_SCALES:
                for turn in TURN_RATES:
                    variant = replace(
                        gait,
                        crab_angle=angle,
                        turn_rate=turn,
                        body_velocity=gait.body_velocity * scale,
                    )
                    out.append(to_omni_genotype(variant))
    return np.array(out)


#: one step of each gene under a damage, with its largest tilt: (n, 4)
_measure = partial(step_table, tilt=True)


def compute_specialists(
    archive: Archive,
    damages: Sequence[Damage],
    engine: str,
    step_duration: float,
    ceiling_dirs: Sequence[str | os.PathLike],
    min_stance_legs: int = 3,
    workers: int = 1,
    progress: Callable[[int, int], None] | None = None,
    source_kinds: Sequence[str] = SOURCE_KINDS,
) -> Specialists:
    """
    Choose the specialists and play each for one step intact and under each damage.

    They are made for the intact robot and the ``damages`` whose every leg's damage is of
    ``source_kinds``.
    """
    sources = [d for d in damages if d.legs and all(leg.kind in source_kinds for leg in d.legs)]
    genes = variants(
        archive, source_gaits(archive, sources, engine, ceiling_dirs, min_stance_legs)
    )
    intact = _measure((engine, None, step_duration, genes))[:, :3]
    reachable = np.any(intact != 0.0, axis=1)  # a gait its feet cannot follow does not move
    genes, intact = genes[reachable], intact[reachable]
    jobs = [(engine, d, step_duration, genes) for d in damages]
    done: list[np.ndarray] = []

    def collect(results) -> None:
        for out in results:
            done.append(out)
            if progress is not None:
                progress(len(done), len(jobs))

    collect(map_in_workers(_measure, jobs, workers))
    table = np.stack(done) if done else np.zeros((0, len(genes), 4))
    return Specialists(genes, intact, table[..., :3], tuple(damages), step_duration, table[..., 3])


def specialists_key(sp: Specialists, engine: str) -> dict:
    """Return everything the specialists' steps depend on (the bank's key of their genes)."""
    return {'format': FORMAT, 'steps': bank_key(sp.repertoire(engine), engine, sp.damages)}


def save_specialists(
    path: str | os.PathLike,
    sp: Specialists,
    engine: str,
    archive: Archive,
    min_stance_legs: int,
    source_kinds: Sequence[str] = SOURCE_KINDS,
) -> None:
    """Write ``sp`` to ``path`` atomically, with its key and where it came from."""
    source = {
        'map_sha256': map_digest(archive),
        'min_stance_legs': min_stance_legs,
        'turn_rates': list(TURN_RATES),
        'source_kinds': list(source_kinds),
    }
    buf = io.BytesIO()
    np.savez_compressed(
        buf,
        key=np.array(json.dumps(specialists_key(sp, engine), sort_keys=True)),
        source=np.array(json.dumps(source, sort_keys=True)),
        genotypes=sp.genotypes,
        intact=sp.intact,
        steps=sp.steps,
        tilt=sp.tilt,
    )
    atomic_write_bytes(Path(path), buf.getvalue())


def load_specialists(
    path: str | os.PathLike, engine: str, damages: Sequence[Damage], step_duration: float
) -> tuple[Specialists | None, str]:
    """Return (the specialists in ``path``, '') if they fit these damages, else (None, why)."""
    try:
        data = read_npz(path, ('key', 'genotypes', 'intact', 'steps', 'tilt'))
        stored = json_array(data['key'], f'{path}: the key')
        genes, intact, steps, tilt = (
            float_array(data[name], f'{path}: {name}')
            for name in ('genotypes', 'intact', 'steps', 'tilt')
        )
    except FileNotFoundError:
        return None, f'no specialists at {path}'
    except UnreadableFile as exc:
        return None, f'not a readable specialists file: {exc}'
    k = len(genes)
    if (
        genes.ndim != 2
        or intact.shape != (k, 3)
        or steps.shape != (len(damages), k, 3)
        or tilt.shape != (len(damages), k)
        or not all(np.all(np.isfinite(a)) for a in (genes, intact, steps, tilt))
        or not np.all((genes >= 0.0) & (genes <= 1.0))
    ):
        return None, (
            f'{path} holds genotypes {genes.shape}, steps {steps.shape}: not finite specialists'
            f' for {len(damages)} damages'
        )
    sp = Specialists(genes, intact, steps, tuple(damages), step_duration, tilt)
    key = specialists_key(sp, engine)
    if stored != key:
        inner = stored.get('steps') if isinstance(stored, dict) else None
        differ = sorted(
            n
            for n in key['steps']
            if not isinstance(inner, dict) or inner.get(n) != key['steps'][n]
        )
        what = ', '.join(differ) if differ else 'format'
        return None, f'{path} was made for another {what}'
    return sp, ''


def with_specialists(
    repertoire: Repertoire, bank: StepBank, path: str | os.PathLike, max_tilt: float
) -> tuple[Repertoire, StepBank, int, str]:
    """
    Return the repertoire and bank with the specialists in ``path`` that stay upright appended.

    Also how many were appended, and why none were ('' when they were): the one way
    navigate_node, run_navigation and the experiment take them.
    """
    sp, why = load_specialists(path, repertoire.engine, bank.damages, repertoire.step_duration)
    if sp is None:
        return repertoire, bank, 0, why
    sp = sp.stable(max_tilt)
    return (*extend(repertoire, bank, sp), len(sp), '')


def extend(repertoire: Repertoire, bank: StepBank, sp: Specialists) -> tuple[Repertoire, StepBank]:
    """Return the repertoire and its bank with the specialists appended as more steps."""
    if sp.damages != bank.damages or sp.step_duration != repertoire.step_duration:
        raise ValueError('the specialists were measured under other damages or step duration')
    genes = hashlib.sha256(np.ascontiguousarray(sp.genotypes, dtype='<f8').tobytes()).hexdigest()
    joined = Repertoire(
        np.concatenate([repertoire.niches, np.full(len(sp), -1)]),
        np.concatenate([repertoire.moves, sp.intact[:, :2]]),
        np.concatenate([repertoire.heading_error, np.abs(sp.intact[:, 2])]),
        np.concatenate([repertoire.genotypes, sp.genotypes]),
        repertoire.step_duration,
        f'{repertoire.digest}+{genes[:8]}',
        repertoire.engine,
    )
    steps = np.concatenate([bank.steps, sp.steps], axis=1)
    before = np.full(bank.steps.shape[:2], np.nan) if bank.tilt is None else bank.tilt
    tilt = np.concatenate([before, sp.tilt], axis=1)
    return joined, StepBank(bank.damages, steps, bank.tripod, bank.intact_tripod, tilt)


def shipped_specialists() -> Path:
    """Return where the shipped repertoire's specialists are (installed, else the source tree)."""
    return shipped_map(NAVIGATION_SPECIALISTS, PACKAGE)
