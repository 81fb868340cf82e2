# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
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
  coxa and femur still move;
* ``unpowered``: one, two or three of the leg's servos are dead (``joints``). A Dynamixel that
  stops answering has dropped its torque, so its joint is free, with only the passive friction of
  its back-driven gearbox (``DEAD_SERVO_FRICTION``, ``DEAD_SERVO_ARMATURE``). The firmware folds
  the leg as far as its live joints can (FOLD POLICY below);
* ``shortened``: the tibia is cut to ``strength`` (0.2-0.9) of its length, as in Cully et al.
  2015; the leg is still walked with the intact leg's kinematics.

FOLD POLICY (the robot's firmware, ``firmware/``, does the same when its servo health check finds
a dead servo): every live joint of a leg with a dead servo goes to the failure pose (coxa 0,
femur 90, tibia -165 degrees) and stays there; dead joints are left free. With a dead coxa the
leg is still folded up; with a dead femur the leg hangs, its tibia folded in so that it drags
least; with a dead tibia the femur is raised and the tibia hangs from it.

At most two legs are damaged (the thesis's scenarios never damage more).
"""

from __future__ import annotations

from dataclasses import dataclass
import functools
import math
from typing import Iterable, Mapping, Sequence

from hexapod_description import N_LEGS
import numpy as np

DAMAGE_KINDS = ('lifted', 'locked', 'weak', 'no_tibia', 'unpowered', 'shortened')
#: A leg's joints, in slot order.
JOINTS = ('coxa', 'femur', 'tibia')
#: Coulomb friction of a dead (unpowered, back-driven) Dynamixel's joint [N m] and its gearbox's
#: reflected inertia [kg m^2]: the best fit by system identification of MX-64 / MX-106 servos
#: (MuJoCo Menagerie ``dynamixel_2r``, Duclusaud et al. 2024, arXiv:2410.08650). The RX-64 has
#: the MX-64's motor and 200:1 gearbox; the RX-28's (193:1) are taken to be the same. With its
#: driver off the motor's windings are open, so no back-EMF damping is left.
DEAD_SERVO_FRICTION = 0.1
DEAD_SERVO_ARMATURE = 0.005
#: The fraction of its tibia a shortened leg keeps: range and default (ITE's shortened leg).
SHORTENED_RANGE = (0.2, 0.9)
DEFAULT_SHORTENED = 0.5
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
    """
    One damaged leg: its number (1..6), the kind and its amount.

    ``strength``: for ``weak`` the fraction of torque and gain left, for ``shortened`` the
    fraction of the tibia left (1 otherwise). ``joints``: for ``unpowered``, the dead joints.
    """

    leg: int
    kind: str = 'lifted'
    strength: float = 1.0
    joints: tuple[str, ...] = ()

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
        elif self.kind == 'shortened':
            lo, hi = SHORTENED_RANGE
            if not (math.isfinite(self.strength) and lo <= self.strength <= hi):
                raise ValueError(
                    f'a shortened leg keeps a fraction in [{lo}, {hi}] of its tibia, '
                    f'got {self.strength!r} for leg {self.leg}'
                )
        elif self.strength != 1.0:
            raise ValueError(
                f'only a weak or shortened leg has a strength; leg {self.leg} is {self.kind}'
            )
        joints = tuple(self.joints)
        if self.kind == 'unpowered':
            unknown = [j for j in joints if j not in JOINTS]
            if unknown or not joints or len(set(joints)) != len(joints):
                raise ValueError(
                    f'an unpowered leg names its dead joints, each once, from '
                    f'{", ".join(JOINTS)}; got {list(joints)} for leg {self.leg}'
                )
            joints = tuple(j for j in JOINTS if j in joints)  # slot order
        elif joints:
            raise ValueError(
                f'only an unpowered leg has dead joints; leg {self.leg} is {self.kind}'
            )
        object.__setattr__(self, 'joints', joints)

    @property
    def label(self) -> str:
        """Return e.g. ``3 locked``, ``4 weak 0.33`` or ``2 unpowered femur+tibia``."""
        return f'{self.leg} {self.condition}'

    @property
    def condition(self) -> str:
        """Return what is wrong with the leg, e.g. ``locked`` or ``unpowered femur``."""
        if self.kind in ('weak', 'shortened'):
            return f'{self.kind} {self.strength:.2f}'
        return f'{self.kind} {"+".join(self.joints)}' if self.joints else self.kind

    def dead_slots(self) -> list[int]:
        """Joint slots (URDF order) of this leg's dead servos."""
        return [3 * (self.leg - 1) + JOINTS.index(j) for j in self.joints]


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
    def unpowered(cls, dead: Mapping[int, Iterable[str]]) -> Damage:
        """Return the damage of dead servos: leg -> its dead joints (the fold policy applies)."""
        validate_failed_legs(dead)
        return cls(tuple(LegDamage(leg, 'unpowered', joints=tuple(j)) for leg, j in dead.items()))

    @classmethod
    def of(cls, kind: str, legs: Iterable[int], strength: float | None = None) -> Damage:
        """
        Every one of ``legs`` damaged the same way: a kind of :data:`EXPERIMENT_KINDS`.

        ``unpowered_<joint>`` is that joint's servo dead; the amount of ``weak`` and
        ``shortened`` is their default unless ``strength`` is given, or the kind names it
        (``shortened:0.75``: a tibia cut to three quarters). ``A+B`` is two kinds at once: two
        legs, the lower-numbered one A, the other B.
        """
        if ':' in kind and '+' not in kind:
            kind, strength = split_amount(kind)
        if '+' in kind:
            kinds, legs_t = kind.split('+'), validate_failed_legs(legs)
            if len(kinds) != len(legs_t) or len(kinds) != MAX_FAILED_LEGS:
                raise ValueError(
                    f'damage kind {kind!r} is two kinds at once, one for each of two legs;'
                    f' the legs are {list(legs_t)}'
                )
            parts = [cls.of(k, [leg], strength).legs[0] for k, leg in zip(kinds, legs_t)]
            return cls(tuple(parts))
        joints: tuple[str, ...] = ()
        if kind.startswith('unpowered_'):
            kind, joints = 'unpowered', (kind.removeprefix('unpowered_'),)
        if strength is None:
            strength = default_amount(kind)
        legs_t = validate_failed_legs(legs)
        return cls(tuple(LegDamage(leg, kind, strength, joints) for leg in legs_t))

    @property
    def failed_legs(self) -> tuple[int, ...]:
        """Return the damaged legs' numbers, sorted."""
        return tuple(d.leg for d in self.legs)

    @property
    def thesis(self) -> bool:
        """Whether this is a thesis scenario: every damaged leg lifted (or none damaged)."""
        return all(d.kind == 'lifted' for d in self.legs)

    def as_lists(self) -> tuple[list[int], list[str], list[float], list[str]]:
        """Return the lists :func:`damage_from_lists` takes: legs, kinds, strengths, joints."""
        return (
            list(self.failed_legs),
            [d.kind for d in self.legs],
            [float(d.strength) for d in self.legs],
            ['+'.join(d.joints) for d in self.legs],
        )

    def kind_of(self, leg: int) -> str | None:
        """Return the damage of ``leg``, or None if it is healthy."""
        return next((d.kind for d in self.legs if d.leg == leg), None)

    def strength_of(self, leg: int) -> float:
        """Fraction of torque and gain left to ``leg``'s servos (1 unless weak)."""
        return next((d.strength for d in self.legs if d.leg == leg and d.kind == 'weak'), 1.0)

    def tibia_fraction(self, leg: int) -> float:
        """Fraction of its tibia ``leg`` keeps (1 unless shortened)."""
        return next((d.strength for d in self.legs if d.leg == leg and d.kind == 'shortened'), 1.0)

    def dead_slots(self) -> np.ndarray:
        """Joint slots (URDF order) whose servos are dead: free joints."""
        return np.array(sorted(s for d in self.legs for s in d.dead_slots()), dtype=int)

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

        Lifted legs hold the failure pose, locked legs the standing pose, and the live joints of
        an unpowered leg the failure pose (the fold policy).
        """
        slots: list[int] = []
        values: list[float] = []
        for d in self.legs:
            if d.kind in ('lifted', 'unpowered'):
                pose: Sequence[float] = FAILURE_POSE
            elif d.kind == 'locked':
                first = 3 * (d.leg - 1)
                stand = standing_pose()
                pose = stand[first:][:3]
            else:
                continue
            dead = set(d.dead_slots())
            for k in range(3):
                if 3 * (d.leg - 1) + k not in dead:
                    slots.append(3 * (d.leg - 1) + k)
                    values.append(float(pose[k]))
        return np.array(slots, dtype=int), np.array(values, dtype=float)


#: The damage kinds experiments and benchmarks report, one per damage (``Damage.of``).
EXPERIMENT_KINDS = (
    'lifted',
    'unpowered_coxa',
    'unpowered_femur',
    'unpowered_tibia',
    'locked',
    'weak',
    'no_tibia',
    'shortened',
)


def split_amount(kind: str) -> tuple[str, float | None]:
    """
    Split ``weak:0.5`` or ``shortened:0.75`` into the kind and its amount (None: none given).

    ValueError says what is wrong: an amount on a kind that has none, or one that is no number.
    """
    name, sep, amount = kind.partition(':')
    if not sep:
        return kind, None
    if name not in ('weak', 'shortened'):
        raise ValueError(f'damage kind {kind!r}: only weak and shortened legs take an amount')
    try:
        return name, float(amount)
    except ValueError:
        raise ValueError(f'damage kind {kind!r}: the amount after ":" must be a number') from None


def check_experiment_kind(kind: str) -> str:
    """Return ``kind`` when :meth:`Damage.of` takes it, else raise ValueError saying what does."""
    parts = [split_amount(part) for part in kind.split('+')]
    if len(parts) > MAX_FAILED_LEGS or any(name not in EXPERIMENT_KINDS for name, _ in parts):
        raise ValueError(
            f'damage kind {kind!r} is none of {", ".join(EXPERIMENT_KINDS)} (weak and shortened'
            ' with an amount as weak:0.5), nor two of them joined by "+" (two legs, two kinds)'
        )
    for name, amount in parts:  # the amount within its range
        if amount is not None:
            LegDamage(1, name, amount)
    return kind


def default_amount(kind: str) -> float:
    """Return the ``strength`` a leg of ``kind`` gets when none is given."""
    return {'weak': DEFAULT_WEAK_STRENGTH, 'shortened': DEFAULT_SHORTENED}.get(kind, 1.0)


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
    Parse ``LEG:KIND[:AMOUNT]`` items separated by commas, e.g. ``1:locked,4:weak:0.3``.

    AMOUNT is a weak leg's strength, a shortened leg's tibia fraction, or an unpowered leg's dead
    joints joined by ``+`` (``2:unpowered:femur+tibia``). An empty text is the intact robot.
    ValueError names the item that is wrong.
    """
    items = [item.strip() for item in text.split(',') if item.strip()]
    legs = []
    for item in items:
        parts = item.split(':')
        if not 2 <= len(parts) <= 3:
            raise ValueError(
                f'damage item {item!r} is not LEG:KIND, LEG:weak|shortened:AMOUNT or '
                'LEG:unpowered:JOINT[+JOINT...]'
            )
        kind = parts[1].strip()
        joints: tuple[str, ...] = ()
        try:
            leg = int(parts[0])
            if kind == 'unpowered':
                joints = tuple(parts[2].split('+')) if len(parts) == 3 else ()
                strength = 1.0
            else:
                strength = float(parts[2]) if len(parts) == 3 else default_amount(kind)
        except ValueError:
            raise ValueError(f'damage item {item!r}: leg must be an integer, amount a number')
        legs.append(LegDamage(leg, kind, strength, joints))
    return Damage(tuple(legs))


def damage_from_lists(
    legs: Sequence[int],
    kinds: Sequence[str] = (),
    strengths: Sequence[float] = (),
    joints: Sequence[str] = (),
) -> Damage:
    """
    Return the damage of parallel lists, as a SetLegFailure request carries it.

    ``kinds`` empty: every leg lifted. ``strengths`` empty, or 0 for a leg: the default amount
    of a weak or shortened leg. ``joints``: per leg, an unpowered leg's dead joints joined by
    ``+`` ('' for other kinds). ValueError says what is wrong (lists of different lengths, a
    repeated leg, an amount or joints given to a leg of another kind).
    """
    legs = list(legs)
    for name, values in (('damage kinds', kinds), ('strengths', strengths), ('joints', joints)):
        if values and len(values) != len(legs):
            raise ValueError(f'{len(values)} {name} for {len(legs)} legs: give one per leg')
    out = []
    for i, leg in enumerate(legs):
        kind = str(kinds[i]) if kinds else 'lifted'
        value = float(strengths[i]) if strengths else 0.0
        if value == 0.0:
            value = default_amount(kind)
        dead = tuple(j for j in str(joints[i]).split('+') if j) if joints else ()
        out.append(LegDamage(leg, kind, value, dead))
    return Damage(tuple(out))


def applied_message(damage: Damage) -> str:
    """Say what damage the simulator now has (the thesis's lifted legs by their numbers)."""
    if damage.thesis:
        return f'failed legs: {list(damage.failed_legs) or "none"}'
    return f'damage: {damage.label}'
