# Copyright 2026 Hexapod adaptation team
# All rights reserved.
#
# Permission is hereby granted, free of charge, to any person obtaining a copy
# of this software and associated documentation files (the "Software"), to deal
# in the Software without restriction, including without limitation the rights
# to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
# copies of the Software, and to permit persons to whom the Software is
# furnished to do so, subject to the following conditions:
#
# The above copyright notice and this permission notice shall be included in all
# copies or substantial portions of the Software.
#
# THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
# IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
# FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
# AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
# LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
# OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
# SOFTWARE.
"""
Leg damage beyond the thesis's lifted legs: the simulator's damage types (ROS-free).

The thesis's failure scenarios (5.1.2, S1-S4) lift a failed leg into a folded pose (table 5.1)
where it touches nothing. Real damage is often otherwise; these kinds are simulated on both
engines and make the tuning set of issue 19 (settings are chosen on them, not on S1-S4):

* ``lifted``: the thesis's failure pose, held by the servos as dead weight;
* ``locked``: the servos hold the angles the leg stood at (the control tripod's standing pose,
  the pose a robot stands in between trials); the leg can still touch the ground and drag;
* ``weak``: the leg's three servos keep ``strength`` (0.05-0.95) of their stall torque and
  proportional gain, so they follow their targets more slowly and sag under load;
* ``no_tibia``: the tibia is gone: it no longer touches anything and weighs (almost) nothing;
  coxa and femur still move.

At most two legs are damaged (the thesis's scenarios never damage more).
"""

from __future__ import annotations

from dataclasses import dataclass
import functools
import math
from typing import Iterable, Sequence

from hexapod_description import N_LEGS
import numpy as np

DAMAGE_KINDS = ('lifted', 'locked', 'weak', 'no_tibia')
#: Failure pose of a lifted leg (thesis table 5.1): coxa 0, femur 90, tibia -165 degrees.
FAILURE_POSE = (0.0, math.radians(90.0), math.radians(-165.0))
MAX_FAILED_LEGS = 2
WEAK_STRENGTH_RANGE = (0.05, 0.95)
#: Strength of a weak leg when none is given: a third of its torque and gain.
DEFAULT_WEAK_STRENGTH = 1.0 / 3.0
#: Mass left to a lost tibia's body [kg] (an engine needs a positive mass on a moving body).
LOST_TIBIA_MASS = 1e-3


@dataclass(frozen=True)
class LegDamage:
    """One damaged leg: its number (1..6), the kind and, for ``weak``, the strength left."""

    leg: int
    kind: str = 'lifted'
    strength: float = 1.0

    def __post_init__(self) -> None:
        if isinstance(self.leg, bool) or not isinstance(self.leg, (int, np.integer)):
            raise ValueError(f'leg numbers must be integers 1..6, got {self.leg!r}')
        if not 1 <= int(self.leg) <= N_LEGS:
            raise ValueError(f'leg {self.leg} does not exist: legs are numbered 1..6')
        object.__setattr__(self, 'leg', int(self.leg))
        if self.kind not in DAMAGE_KINDS:
            raise ValueError(
                f'unknown damage kind {self.kind!r} for leg {self.leg}; '
                f'known: {", ".join(DAMAGE_KINDS)}'
            )
        lo, hi = WEAK_STRENGTH_RANGE
        if self.kind == 'weak':
            if not (math.isfinite(self.strength) and lo <= self.strength <= hi):
                raise ValueError(
                    f'a weak leg keeps a strength in [{lo}, {hi}] of its servos, '
                    f'got {self.strength!r} for leg {self.leg}'
                )
        elif self.strength != 1.0:
            raise ValueError(f'only a weak leg has a strength; leg {self.leg} is {self.kind}')

    @property
    def label(self) -> str:
        """Return e.g. ``3 locked`` or ``4 weak 0.33``."""
        text = f'{self.leg} {self.kind}'
        return f'{text} {self.strength:.2f}' if self.kind == 'weak' else text


@dataclass(frozen=True)
class Damage:
    """What is wrong with the robot: at most two damaged legs, sorted by leg (none = intact)."""

    legs: tuple[LegDamage, ...] = ()

    def __post_init__(self) -> None:
        legs = tuple(sorted(self.legs, key=lambda d: d.leg))
        numbers = [d.leg for d in legs]
        if len(set(numbers)) != len(numbers):
            raise ValueError(f'a leg is damaged twice: legs {numbers}')
        if len(legs) > MAX_FAILED_LEGS:
            raise ValueError(
                f'at most {MAX_FAILED_LEGS} legs can fail (the thesis scenarios S0-S4); '
                f'got {len(legs)}: {numbers}'
            )
        object.__setattr__(self, 'legs', legs)

    @classmethod
    def lifted(cls, legs: Iterable[int]) -> Damage:
        """Return the thesis's damage: these legs lifted into the failure pose."""
        return cls(tuple(LegDamage(leg) for leg in validate_failed_legs(legs)))

    @classmethod
    def of(cls, kind: str, legs: Iterable[int], strength: float | None = None) -> Damage:
        """Every one of ``legs`` damaged the same way."""
        if strength is None:
            strength = DEFAULT_WEAK_STRENGTH if kind == 'weak' else 1.0
        return cls(tuple(LegDamage(leg, kind, strength) for leg in validate_failed_legs(legs)))

    @property
    def failed_legs(self) -> tuple[int, ...]:
        """Return the damaged legs' numbers, sorted."""
        return tuple(d.leg for d in self.legs)

    @property
    def thesis(self) -> bool:
        """Whether this is a thesis scenario: every damaged leg lifted (or none damaged)."""
        return all(d.kind == 'lifted' for d in self.legs)

    def kind_of(self, leg: int) -> str | None:
        """Return the damage of ``leg``, or None if it is healthy."""
        return next((d.kind for d in self.legs if d.leg == leg), None)

    def strength_of(self, leg: int) -> float:
        """Fraction of torque and gain left to ``leg``'s servos (1 unless weak)."""
        return next((d.strength for d in self.legs if d.leg == leg), 1.0)

    @property
    def label(self) -> str:
        """Return e.g. ``legs 1+5 lifted`` or ``leg 3 locked, leg 4 weak 0.33`` (``intact``)."""
        if not self.legs:
            return 'intact'
        if self.thesis:
            legs = 'legs' if len(self.legs) > 1 else 'leg'
            return f'{legs} {"+".join(map(str, self.failed_legs))} lifted'
        return ', '.join(f'leg {d.label}' for d in self.legs)

    def held_slots(self) -> tuple[np.ndarray, np.ndarray]:
        """
        Joint slots (URDF order) the servos hold whatever is commanded, and their angles.

        Lifted legs hold the failure pose, locked legs the standing pose.
        """
        slots: list[int] = []
        values: list[float] = []
        for d in self.legs:
            if d.kind == 'lifted':
                pose: Sequence[float] = FAILURE_POSE
            elif d.kind == 'locked':
                first = 3 * (d.leg - 1)
                stand = standing_pose()
                pose = stand[first:][:3]
            else:
                continue
            slots.extend(3 * (d.leg - 1) + k for k in range(3))
            values.extend(float(v) for v in pose)
        return np.array(slots, dtype=int), np.array(values, dtype=float)


def validate_failed_legs(legs: Iterable[int]) -> tuple[int, ...]:
    """Sorted, de-duplicated legs 1..6, at most two; ValueError says what is wrong."""
    out = []
    for leg in legs:
        if isinstance(leg, bool) or not isinstance(leg, (int, np.integer)):
            raise ValueError(f'leg numbers must be integers 1..6, got {leg!r}')
        if not 1 <= int(leg) <= N_LEGS:
            raise ValueError(f'leg {leg} does not exist: legs are numbered 1..6')
        out.append(int(leg))
    legs_t = tuple(sorted(set(out)))
    if len(legs_t) > MAX_FAILED_LEGS:
        raise ValueError(
            f'at most {MAX_FAILED_LEGS} legs can fail (the thesis scenarios S0-S4); '
            f'got {len(legs_t)}: {list(legs_t)}'
        )
    return legs_t


def as_damage(damage: Damage | Iterable[int]) -> Damage:
    """Return a :class:`Damage` as is, or leg numbers as those legs lifted (the thesis's)."""
    return damage if isinstance(damage, Damage) else Damage.lifted(damage)


@functools.lru_cache(maxsize=1)
def _standing_pose() -> tuple[float, ...]:
    from hexapod_gait import build_joint_table, preset

    table = build_joint_table(preset('control'), rate=100.0)
    return tuple(float(v) for v in table.positions[0])


def standing_pose() -> np.ndarray:
    """Joint angles (18, URDF order) the robot stands in: the control tripod's first pose."""
    return np.array(_standing_pose())


def parse_damage(text: str) -> Damage:
    """
    Parse ``LEG:KIND[:STRENGTH]`` items separated by commas, e.g. ``1:locked,4:weak:0.3``.

    An empty text is the intact robot. ValueError names the item that is wrong.
    """
    items = [item.strip() for item in text.split(',') if item.strip()]
    legs = []
    for item in items:
        parts = item.split(':')
        if not 2 <= len(parts) <= 3:
            raise ValueError(f'damage item {item!r} is not LEG:KIND or LEG:weak:STRENGTH')
        try:
            leg = int(parts[0])
            strength = float(parts[2]) if len(parts) == 3 else None
        except ValueError:
            raise ValueError(f'damage item {item!r}: leg must be an integer, strength a number')
        kind = parts[1].strip()
        if strength is None:
            strength = DEFAULT_WEAK_STRENGTH if kind == 'weak' else 1.0
        legs.append(LegDamage(leg, kind, strength))
    return Damage(tuple(legs))


def damage_from_lists(
    legs: Sequence[int], kinds: Sequence[str] = (), strengths: Sequence[float] = ()
) -> Damage:
    """
    Return the damage of parallel lists, as a SetLegFailure request carries it.

    ``kinds`` empty: every leg lifted. ``strengths`` empty, or 0 for a leg: the default strength
    of a weak leg. ValueError says what is wrong (lists of different lengths, a repeated leg, a
    strength given to a leg that is not weak).
    """
    legs = list(legs)
    if kinds and len(kinds) != len(legs):
        raise ValueError(f'{len(kinds)} damage kinds for {len(legs)} legs: give one per leg')
    if strengths and len(strengths) != len(legs):
        raise ValueError(f'{len(strengths)} strengths for {len(legs)} legs: give one per leg')
    out = []
    for i, leg in enumerate(legs):
        kind = str(kinds[i]) if kinds else 'lifted'
        value = float(strengths[i]) if strengths else 0.0
        if value == 0.0:
            value = DEFAULT_WEAK_STRENGTH if kind == 'weak' else 1.0
        out.append(LegDamage(leg, kind, value))
    return Damage(tuple(out))


def applied_message(damage: Damage) -> str:
    """Say what damage the simulator now has (the thesis's lifted legs by their numbers)."""
    if damage.thesis:
        return f'failed legs: {list(damage.failed_legs) or "none"}'
    return f'damage: {damage.label}'
