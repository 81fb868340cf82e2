# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Navigation's damage bank: every repertoire step re-measured under each damage hypothesis.

The navigation counterpart of :mod:`hexapod_adapt.online.bank`: each gait of the repertoire played
for one step (``STEP_DURATION`` s, from rest, collisions not fatal) under each damage of the bank.
The shipped bank (:func:`navigation_bank_damages`) holds every one- and two-leg failure of S1-S4
(the orientations of :data:`hexapod_adapt.online.bank.BANK_DAMAGES`) of each kind in
:data:`NAVIGATION_BANK_KINDS`: legs lifted (the thesis's damage), locked where they stood, and
hanging from a dead femur servo (a real servo failure). The navigator's correction
(:class:`hexapod_navigation.core.correction.CorrectionGP`) weighs these step tables against the
intact repertoire by how well they explain the steps walked, and learns the rest. The bank also
holds the steered tripod's cycle in each crab direction under each damage and intact
(:func:`hexapod_navigation.core.tripod.tripod_cycles`): the planner's prior for the tripod option.

``python -m hexapod_navigation.offline.step_bank_cli`` makes one
(``maps/make_navigation_bank.sh``).

The file is keyed by everything the steps depend on (the repertoire's gaits, the engine and its
settings, the URDF, the scoring rules' version, the damages); a file made for anything else is
not used, and says why. The damages are read back from the file, so a bank made for another
set of damages (``step_bank_cli --kinds``) loads as it is.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
import hashlib
import io
import json
import os
from pathlib import Path
from typing import Callable, Sequence

from hexapod_adapt import BANK_DAMAGES, repertoire_fingerprint, shipped_map, worker_simulator
from hexapod_gait.parameters import from_omni_genotype
from hexapod_navigation.core.repertoire import PACKAGE, Repertoire
from hexapod_navigation.core.tripod import tripod_cycles, tripod_gaits
from hexapod_sim.damage import Damage, LegDamage
from hexapod_sim.evaluation import evaluate_displacements, EVALUATION_VERSION
from hexapod_sim.simulator import start_key
from hexapod_util.files import atomic_write_bytes
from hexapod_util.npz import float_array, json_array, read_npz, UnreadableFile
from hexapod_util.processes import map_in_workers
import numpy as np

FORMAT = 'hexapod-step-bank/v3'  # v2: the steered tripod's cycles; v3: damages of any kind
#: The kinds of damage of the shipped bank (Damage.of's names), each over BANK_DAMAGES' legs.
NAVIGATION_BANK_KINDS = ('lifted', 'locked', 'unpowered_femur')
#: The shipped repertoire's bank (``maps/navigation_bank.npz``).
NAVIGATION_BANK = 'navigation_bank.npz'


@dataclass(frozen=True)
class StepBank:
    """
    The repertoire's steps under each of ``damages``: ``steps[h, i]`` = (dx, dy, dyaw).

    And the steered tripod's cycles (:func:`hexapod_navigation.core.tripod.tripod_cycles`):
    ``tripod[h, k]`` under each damage, ``intact_tripod[k]`` on the intact robot.
    """

    damages: tuple[Damage, ...]
    steps: np.ndarray  # (h, n, 3): m, m, rad, in the step's start frame
    tripod: np.ndarray  # (h, 8, 3): one cycle of each crab direction, in its start frame
    intact_tripod: np.ndarray  # (8, 3)
    #: (h, n) rad: each step's largest tilt (roll or pitch) under each damage, NaN where not
    #: measured (the repertoire's own steps); None: none measured
    tilt: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.damages)

    def tripods(self) -> np.ndarray:
        """Return the tripod's cycles intact and under each damage, (1 + h, 8, 3)."""
        return np.concatenate([self.intact_tripod[None], self.tripod])

    def index_of(self, damage: Damage) -> int | None:
        """
        Return the row that models ``damage`` (None if the bank holds nothing that does).

        The damage's own row, or else, for legs whose only dead servo is the coxa, the row of
        those legs lifted: the fold policy holds femur and tibia in the failure pose, so such a
        leg is folded as a lifted one (its coxa free in the air).
        """
        if damage in self.damages:
            return self.damages.index(damage)
        if damage.legs and all(
            d.kind == 'unpowered' and d.joints == ('coxa',) for d in damage.legs
        ):
            folded = Damage.lifted(damage.failed_legs)
            if folded in self.damages:
                return self.damages.index(folded)
        return None

    def without(self, damage: Damage) -> StepBank:
        """Return the bank less ``damage`` (an experiment's damage left out of its hypotheses)."""
        keep = [i for i, d in enumerate(self.damages) if d != damage]
        return StepBank(
            tuple(self.damages[i] for i in keep),
            self.steps[keep],
            self.tripod[keep],
            self.intact_tripod,
            None if self.tilt is None else self.tilt[keep],
        )


def navigation_bank_damages(kinds: Sequence[str] = NAVIGATION_BANK_KINDS) -> tuple[Damage, ...]:
    """Return every one- and two-leg failure of S1-S4 of each of ``kinds``, kind by kind."""
    return tuple(Damage.of(kind, d.failed_legs) for kind in kinds for d in BANK_DAMAGES)


def _damage_rows(damages: Sequence[Damage]) -> list[list[list]]:
    """Return damages as JSON rows: per damage, per leg [leg, kind, strength, [joints]]."""
    return [
        [[d.leg, d.kind, d.strength, list(d.joints)] for d in damage.legs] for damage in damages
    ]


def _damages_of(rows: object) -> tuple[Damage, ...]:
    """Return the damages of :func:`_damage_rows`' rows; ValueError if they are not such rows."""
    if not isinstance(rows, list):
        raise ValueError(f'damages must be a list, got {type(rows).__name__}')
    out = []
    for row in rows:
        if not isinstance(row, list):
            raise ValueError(f'a damage must be a list of legs, got {row!r}')
        legs = []
        for item in row:
            if not (isinstance(item, list) and len(item) == 4 and isinstance(item[3], list)):
                raise ValueError(
                    f'a damaged leg must be [leg, kind, strength, [joints]], got {item!r}'
                )
            leg, kind, strength, joints = item
            if not isinstance(kind, str) or not isinstance(strength, (int, float)):
                raise ValueError(
                    f'a damaged leg must be [leg, kind, strength, [joints]], got {item!r}'
                )
            legs.append(LegDamage(leg, kind, float(strength), tuple(str(j) for j in joints)))
        out.append(Damage(tuple(legs)))
    return tuple(out)


def bank_key(repertoire: Repertoire, engine: str, damages: Sequence[Damage]) -> dict:
    """Return everything a step bank depends on (stored in its file)."""
    fp = repertoire_fingerprint(engine)
    tripod = json.dumps(
        [{k: np.asarray(v).tolist() for k, v in asdict(g).items()} for g in tripod_gaits()],
        sort_keys=True,
    )
    genes = hashlib.sha256(
        np.ascontiguousarray(repertoire.genotypes, dtype='<f8').tobytes()
    ).hexdigest()
    return {
        'format': FORMAT,
        'genotypes_sha256': genes,
        'engine': engine,
        'simulator': fp['simulator']['settings_sha256'],
        'urdf_sha256': fp['urdf_sha256'],
        'genotype_mapping': fp['genotype_mapping'],
        'step_duration': repertoire.step_duration,
        'collisions_fatal': False,
        'evaluation_version': EVALUATION_VERSION,
        'damages': _damage_rows(damages),
        **start_key(damages),  # a locked leg's start (a bank made before it: stale)
        'tripod_sha256': hashlib.sha256(tripod.encode()).hexdigest(),
    }


def step_table(
    args: tuple[str, Damage | None, float, np.ndarray], tilt: bool = False
) -> np.ndarray:
    """
    Play omni ``genes`` for one step of ``duration`` s each under ``damage``: (n, 3) moves.

    ``tilt``: (n, 4), each step's largest tilt during it
    (:attr:`hexapod_sim.evaluation.Displacement.peak_tilt`) last.
    """
    engine, damage, duration, genes = args
    moves = evaluate_displacements(
        list(genes),
        worker_simulator(engine),
        duration,
        collisions_fatal=False,
        failed_legs=damage,
        decode=from_omni_genotype,
    )
    rows = [(m.x, m.y, m.yaw, m.peak_tilt) if tilt else (m.x, m.y, m.yaw) for m in moves]
    return np.array(rows, dtype=float).reshape(-1, 4 if tilt else 3)


def compute_step_bank(
    repertoire: Repertoire,
    engine: str,
    damages: Sequence[Damage] | None = None,
    workers: int = 1,
    chunk: int = 64,
    progress: Callable[[int, int], None] | None = None,
) -> StepBank:
    """Play every repertoire gait for one step under each damage (default: the shipped set)."""
    if damages is None:
        damages = navigation_bank_damages()
    starts = range(chunk, len(repertoire), chunk)
    parts = [p for p in np.split(repertoire.genotypes, starts) if len(p)]
    jobs = [(engine, d, repertoire.step_duration, p) for d in damages for p in parts]
    done: list[np.ndarray] = []

    def collect(results) -> None:
        for out in results:
            done.append(out)
            if progress is not None:
                progress(len(done), len(jobs))

    collect(map_in_workers(step_table, jobs, workers))
    steps = np.concatenate(done).reshape(len(damages), len(repertoire), 3)
    sim = worker_simulator(engine)  # a few seconds: 8 gaits, 2 cycles, per damage
    tripod = np.array([tripod_cycles(sim, d) for d in damages]).reshape(len(damages), 8, 3)
    return StepBank(tuple(damages), steps, tripod, tripod_cycles(sim, None))


def save_step_bank(
    path: str | os.PathLike, bank: StepBank, repertoire: Repertoire, engine: str
) -> None:
    """Write ``bank`` to ``path`` atomically, with its key."""
    buf = io.BytesIO()
    key = bank_key(repertoire, engine, bank.damages)
    np.savez_compressed(
        buf,
        key=np.array(json.dumps(key, sort_keys=True)),
        steps=bank.steps,
        tripod=bank.tripod,
        intact_tripod=bank.intact_tripod,
    )
    atomic_write_bytes(Path(path), buf.getvalue())


def load_step_bank(
    path: str | os.PathLike,
    repertoire: Repertoire,
    engine: str,
    damages: Sequence[Damage] | None = None,
) -> tuple[StepBank | None, str]:
    """
    Return (the bank in ``path``, '') if it was made for this repertoire, else (None, why).

    ``damages``: the damages it must hold, in order (None: whatever damages it holds).
    """
    try:
        data = read_npz(path, ('key', 'steps', 'tripod', 'intact_tripod'))
        stored = json_array(data['key'], f'{path}: the key')
        steps, tripod, intact_tripod = (
            float_array(data[name], f'{path}: {name}')
            for name in ('steps', 'tripod', 'intact_tripod')
        )
    except FileNotFoundError:
        return None, f'no step bank at {path}'
    except UnreadableFile as exc:
        return None, f'not a readable step bank: {exc}'
    if not isinstance(stored, dict):
        return None, f'{path} is not a readable step bank (its key is not a JSON object)'
    if damages is None:
        try:
            damages = _damages_of(stored.get('damages'))
        except ValueError as exc:
            return None, f'{path} names no damages a bank can hold ({exc})'
    key = bank_key(repertoire, engine, damages)
    if stored != key:
        differ = sorted(k for k in key if stored.get(k) != key[k])
        return None, f'{path} was made for another {", ".join(differ)}'
    if steps.shape != (len(damages), len(repertoire), 3) or not np.all(np.isfinite(steps)):
        return None, f'{path} holds steps of shape {steps.shape}, not a finite bank'
    if (
        tripod.shape != (len(damages), 8, 3)
        or intact_tripod.shape != (8, 3)
        or not (np.all(np.isfinite(tripod)) and np.all(np.isfinite(intact_tripod)))
    ):
        return None, f'{path} holds tripod cycles of shape {tripod.shape}, not a finite bank'
    return StepBank(tuple(damages), steps, tripod, intact_tripod), ''


def reported_note(bank: StepBank | None, damage: Damage | None, share: float) -> str:
    """Say, for the log, what navigation makes of the ``damage`` the robot reported."""
    if damage is None:
        return 'navigation learns the damage as it walks'
    if share <= 0:
        return f'navigation learns {damage.label} as it walks (prior_reported is 0)'
    if bank is None:
        return f'no damage bank: navigation learns {damage.label} as it walks'
    row = bank.index_of(damage)
    if row is None:
        return f'the damage bank does not model {damage.label}: navigation learns it as it walks'
    return (
        f"navigation favours the damage bank's {bank.damages[row].label} from the next goal"
        f' (prior share {share:g})'
    )


def shipped_step_bank() -> Path:
    """Return where the shipped repertoire's bank is (installed, else the source tree)."""
    return shipped_map(NAVIGATION_BANK, PACKAGE)
