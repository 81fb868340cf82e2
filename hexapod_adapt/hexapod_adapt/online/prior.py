# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A damage-informed prior: the map re-scored in simulation under the damage known before a run.

Often the failed legs are known: the simulator says what it was given (``sim/damage``), the
robot's servo health check reports a servo that does not answer (``servo_failures``), or the
operator names them in the ``adapt`` request. Then, before the first trial, every gait of the map
is evaluated in simulation with that damage (a ceiling, :mod:`hexapod_adapt.online.ceiling`,
cached) and M-BOA starts from those speeds instead of the intact map's. Robot trials still decide:
the prior is only a prior. A re-score keeps speeds, not tilts, so before a run tries a gait,
:class:`TipScreen` walks it again with the body's tilt recorded, and a gait that tilts past the
trials' tip guard in simulation is never tried (M-BOA vetoes it).

:class:`KnownDamage` keeps what the node has been told and refuses what makes no sense, saying
why; :func:`damage_prior` re-scores the map.
"""

from __future__ import annotations

from dataclasses import dataclass
import os
import time
from typing import Any, Callable, Sequence

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.online.ceiling import ceiling, evaluate_tilts, Rescoring
from hexapod_description import N_LEGS
from hexapod_sim.damage import Damage, damage_from_lists, JOINTS, MAX_FAILED_LEGS
import numpy as np


@dataclass(frozen=True)
class DamagePrior:
    """The map's gaits re-scored under ``damage`` on ``engine``: M-BOA's prior mean."""

    damage: Damage
    engine: str
    speeds: np.ndarray  # (elites,) m/s, in the order of archive.elite_indices()
    seconds: float  # wall-clock time it took (0 if it was cached)

    def describe(self) -> str:
        """Say what the prior is, e.g. ``the map re-scored on mujoco under legs 1+4 lifted``."""
        return (
            f'the map re-scored on {self.engine} under {self.damage.label} '
            f'(best {float(np.max(self.speeds)):.3f} m/s'
            + (f', {self.seconds:.0f} s)' if self.seconds >= 1 else ', cached)')
        )


def damage_prior(
    archive: Archive,
    damage: Damage,
    engine: str,
    cache_dir: str | os.PathLike | None,
    read_dirs: Sequence[str | os.PathLike] = (),
    workers: int = 1,
    progress: Callable[[int, int], None] | None = None,
) -> DamagePrior:
    """Re-score every gait of ``archive`` under ``damage`` on ``engine`` (cached)."""
    t0 = time.monotonic()
    c = ceiling(archive, damage, engine, cache_dir, workers, read_dirs, progress)
    return DamagePrior(damage, engine, c.speeds, time.monotonic() - t0)


class TipScreen:
    """
    Whether a gait tips in simulation under the damage: a run asks before it tries one.

    ``tilts_of(positions)`` returns how far the gaits at those positions (the prior's order, that
    of ``archive.elite_indices()``) tilt the body [rad]; ``guard`` is the trials' tip guard. Each
    gait is walked once, when first asked about (a walk of one gait, about 0.1 s on MuJoCo),
    and its tilt is kept.
    """

    def __init__(self, tilts_of: Callable[[np.ndarray], np.ndarray], guard: float) -> None:
        self._tilts_of, self.guard = tilts_of, float(guard)
        self.tilts: dict[int, float] = {}  # position -> peak tilt [rad], each walked once

    @classmethod
    def worst_of(cls, screens: Sequence[TipScreen]) -> TipScreen:
        """
        Return a screen of several damages at once: a gait's tilt is the largest of theirs.

        A gait that tips under any of them is vetoed (the damage is one of them, which is not
        known). Each screen still walks each gait once.
        """
        if not screens:
            raise ValueError('worst_of needs at least one screen')

        def tilts_of(positions: np.ndarray) -> np.ndarray:
            worst = []
            for position in map(int, positions):
                for screen in screens:
                    screen.tips(position)
                worst.append(max(screen.tilts[position] for screen in screens))
            return np.array(worst)

        return cls(tilts_of, min(screen.guard for screen in screens))

    @property
    def tipping(self) -> list[int]:
        """Return the positions walked so far that tilt past the guard, in order."""
        return sorted(i for i, tilt in self.tilts.items() if tilt > self.guard)

    def tips(self, position: int) -> bool:
        """Whether the gait at ``position`` tilts the body past the guard (walked on first ask)."""
        position = int(position)
        if position not in self.tilts:
            self.tilts[position] = float(self._tilts_of(np.array([position]))[0])
        return self.tilts[position] > self.guard

    def best_upright(self, speeds: np.ndarray) -> int | None:
        """
        Return the position of the fastest gait of ``speeds`` that does not tip (None: all tip).

        Walks the gaits from the fastest down until one stays within the guard.
        """
        for position in np.argsort(-np.asarray(speeds, dtype=float), kind='stable'):
            if not self.tips(int(position)):
                return int(position)
        return None


def simulated_tilts(
    archive: Archive, damage: Damage, engine: str
) -> Callable[[np.ndarray], np.ndarray]:
    """Return ``tilts_of`` for a :class:`TipScreen`: gaits walked as their re-score walked them."""
    how = Rescoring.of(archive, damage, engine)
    niches = archive.elite_indices()

    def tilts_of(positions: np.ndarray) -> np.ndarray:
        return evaluate_tilts(how, archive.genotypes[niches[positions]])

    return tilts_of


def servo_report_verdict(
    servo: int, confirmed: bool | None, bridge: str, others: Sequence[str]
) -> str:
    """
    Say why a report that ``servo`` is dead cannot be believed ('' if it can).

    A topic does not tell its subscriber which publisher sent a message (rclpy's message info
    holds no sender), and a sender that left at once is gone from the graph when its message is
    handled. So a report is believed only when ``bridge`` (the bridge node the node is configured
    to use) confirms it holds that servo dead: ``confirmed`` is its answer (None: no answer).
    ``others`` are the other publishers of the topic seen lately, named when a report is not
    believed.
    """
    if confirmed:
        return ''
    names = ', '.join(sorted(set(others)))
    seen = (
        f'; publishers of servo_failures besides the bridge since the last report: {names}'
        if others
        else '; no publisher of servo_failures but the bridge was seen (the sender left at once)'
    )
    if confirmed is None:
        why = f'did not answer whether servo {servo} is dead'
    else:
        why = f'does not hold servo {servo} dead'
    return f'servo report ignored: the bridge {bridge} {why}{seen}'


def requested_damage(
    legs: Sequence[int],
    kinds: Sequence[str] = (),
    strengths: Sequence[float] = (),
    joints: Sequence[str] = (),
) -> Damage | None:
    """
    Return the damage an adapt request names (its parallel lists, as SetLegFailure's), or None.

    No legs: None (the node's own knowledge). ValueError says what is wrong, e.g. kinds given
    without legs, an unknown kind, a joint out of range or three legs.
    """
    if not legs:
        lists = (('kinds', kinds), ('strengths', strengths), ('joints', joints))
        given = [name for name, values in lists if values]
        if given:
            raise ValueError(f'{" and ".join(given)} given without failed_legs: name the legs too')
        return None
    return damage_from_lists(legs, kinds, strengths, joints)


def damage_of_request(request: Any) -> Damage | None:
    """Return :func:`requested_damage` of an Adapt or SetLegFailure request's damage fields."""
    return requested_damage(
        list(request.failed_legs),
        list(request.kinds),
        list(request.strengths),
        list(request.joints),
    )


class KnownDamage:
    """
    What a node has been told of the robot's damage, from the simulator or servo reports.

    Each ``from_*`` method returns a sentence for the log: what was taken, or why it was refused.
    A refused report changes nothing.
    """

    def __init__(self) -> None:
        self.sim: Damage | None = None
        self.servos: dict[int, dict[int, str]] = {}  # URDF leg -> {dead servo id: its joint}
        self.refused: str = ''  # why the servo reports make no usable damage ('' if they do)

    def from_sim(
        self,
        legs: Sequence[int],
        kinds: Sequence[str],
        strengths: Sequence[float],
        joints: Sequence[str] = (),
    ) -> str:
        """Take the simulator's damage (``sim/damage``)."""
        try:
            damage = damage_from_lists(list(legs), list(kinds), list(strengths), list(joints))
        except ValueError as exc:
            return f'simulator damage report refused: {exc}'
        self.sim = damage
        return f'the simulator reports: {damage.label}'

    def from_servo(self, servo: int, urdf_leg: int, joint: str) -> str:
        """Take a servo-failure report (the bridge's ``servo_failures``): that joint is dead."""
        if not 1 <= urdf_leg <= N_LEGS:
            return (
                f'servo {servo} reported dead names no leg (leg {urdf_leg}): not used for the '
                'prior'
            )
        if joint not in JOINTS:
            return (
                f'servo {servo} reported dead names no joint ({joint!r}, not one of '
                f'{", ".join(JOINTS)}): not used for the prior'
            )
        if servo in self.servos.get(urdf_leg, {}):
            return f'servo {servo} (leg {urdf_leg}) reported dead again: already known'
        self.servos.setdefault(urdf_leg, {})[servo] = joint
        if len(self.servos) > MAX_FAILED_LEGS:
            self.refused = (
                f'servo reports name {len(self.servos)} failed legs'
                f' ({sorted(self.servos)}); a damage prior covers at most {MAX_FAILED_LEGS},'
                ' so runs start from the map as it is'
            )
            return self.refused
        return f'servo {servo} reported dead: leg {urdf_leg} {joint} unpowered'

    def forget(self) -> str:
        """Drop the servo reports (after a repair); say what was dropped."""
        known = sorted(s for servos in self.servos.values() for s in servos)
        self.servos, self.refused = {}, ''
        if not known:
            return 'no servo reports to forget'
        return f'forgot the reports of dead servos {known}; runs start from the map as it is'

    def servo_damage(self) -> Damage | None:
        """
        Return the damage the servo reports describe, or None.

        A dead servo leaves its joint free; the robot's firmware folds the leg with the live
        ones (:mod:`hexapod_sim.damage`'s fold policy), so the damage is that leg unpowered.
        """
        if not self.servos or self.refused:
            return None
        return Damage.unpowered({leg: set(s.values()) for leg, s in self.servos.items()})

    def for_run(self, requested: Damage | None, blind: bool) -> tuple[Damage | None, str]:
        """
        Return the damage a run's prior should use, and a sentence saying where it comes from.

        A request's damage wins (the operator's word; :func:`requested_damage`), then the
        simulator's report, then the servo reports (their legs unpowered, folded by the firmware).
        """
        if blind:
            return None, 'the map as it is (blind prior requested)'
        if requested is not None:
            note = ''
            if self.sim is not None and self.sim != requested:
                note = f'; note: the simulator reports {self.sim.label}'
            return requested, f'the request: {requested.label}{note}'
        if self.sim is not None:
            if not self.sim.legs:
                return None, 'the map as it is (the simulator reports no damage)'
            return self.sim, f'the simulator: {self.sim.label}'
        servo = self.servo_damage()
        if servo is not None:
            return servo, f'servo reports: {servo.label}'
        if self.refused:
            return None, f'the map as it is ({self.refused})'
        return None, 'the map as it is (no damage known)'
