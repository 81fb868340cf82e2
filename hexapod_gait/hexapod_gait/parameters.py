# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Gait parameters (thesis table 3.10) as a typed, validated value, and the genotype mapping.

A gait is 2 body parameters (velocity, height), 5 parameters per leg (radius, angle offset,
step height, duty factor, phase offset) and two constants (period, crab angle). MAP-Elites
searches 32 numbers in [0, 1]; :func:`from_genotype` scales them to the ranges of table 4.1.

One extension beyond the thesis: ``turn_rate``, the body's commanded yaw rate [rad/s] (0 in every
thesis gait). With it each leg's stride follows its own direction, the one the body's motion
gives its foot (docs/navigation.md, "Omnidirectional gaits").
"""

from __future__ import annotations

from dataclasses import dataclass, field
import math
from typing import Any, Callable, Mapping, Sequence

from hexapod_description import N_LEGS
import numpy as np

GENOTYPE_SIZE = 2 + 5 * N_LEGS  # 32

#: Walking direction of the map gaits, in base_link: between legs 1 and 6, as in the thesis
#: code's map generation (crab_angle = -pi/6; fitness is measured along this direction).
DEFAULT_CRAB_ANGLE = -math.pi / 6
DEFAULT_PERIOD = 1.0

#: Version of the genotype <-> parameters mapping. Archives record it; change it whenever
#: from_genotype changes so that a map is never read with the wrong meaning.
GENOTYPE_MAPPING_VERSION = 'thesis-4.1/v1'

#: Allowed ranges, inclusive (table 4.1; period and crab angle are fixed by the mapping but
#: any value in these ranges is a valid gait for the controller).
RANGES: dict[str, tuple[float, float]] = {
    'body_velocity': (0.0, 0.5),  # m/s
    'body_height': (0.0, 0.2),  # m
    'period': (0.1, 10.0),  # s
    'crab_angle': (-math.pi, math.pi),  # rad
    'turn_rate': (-1.0, 1.0),  # rad/s (our extension; 0 in the thesis)
    'radius': (0.0, 0.3),  # m
    'angle_offset': (-1.745, 1.745),  # rad
    'step_height': (0.0, 0.2),  # m
    'duty_factor': (0.0, 1.0),  # 1
    'phase_offset': (0.0, 1.0),  # 1
}
UNITS = {
    'body_velocity': 'm/s',
    'body_height': 'm',
    'period': 's',
    'crab_angle': 'rad',
    'turn_rate': 'rad/s',
    'radius': 'm',
    'angle_offset': 'rad',
    'step_height': 'm',
    'duty_factor': '',
    'phase_offset': '',
}
SCALAR_FIELDS = ('body_velocity', 'body_height', 'period', 'crab_angle', 'turn_rate')
LEG_FIELDS = ('radius', 'angle_offset', 'step_height', 'duty_factor', 'phase_offset')


class GaitParameterError(ValueError):
    """A gait parameter is malformed or out of range; ``field`` names it."""

    def __init__(self, field_name: str, message: str):
        super().__init__(f'{field_name}: {message}')
        self.field = field_name


def _range_text(name: str) -> str:
    lo, hi = RANGES[name]
    unit = f' {UNITS[name]}' if UNITS[name] else ''
    return f'[{lo:g}, {hi:g}]{unit}'


def _check_scalar(name: str, value: Any) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise GaitParameterError(name, f'expected a number, got {value!r}') from None
    if not math.isfinite(v):
        raise GaitParameterError(name, f'must be finite, got {v}; allowed {_range_text(name)}')
    lo, hi = RANGES[name]
    if not lo <= v <= hi:
        raise GaitParameterError(name, f'{v:g} is outside the allowed range {_range_text(name)}')
    return v


def _check_leg_array(name: str, value: Any) -> np.ndarray:
    try:
        arr = np.array(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise GaitParameterError(name, f'expected {N_LEGS} numbers, got {value!r}') from None
    if arr.size != N_LEGS:
        raise GaitParameterError(name, f'expected {N_LEGS} values (one per leg), got {arr.size}')
    lo, hi = RANGES[name]
    bad = ~np.isfinite(arr) | (arr < lo) | (arr > hi)
    if bad.any():
        i = int(np.argmax(bad))
        raise GaitParameterError(
            f'{name}[leg {i + 1}]', f'{arr[i]:g} is outside the allowed range {_range_text(name)}'
        )
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class GaitParameters:
    """
    One gait of the kinematic controller (SI units; per-leg arrays are legs 1..6).

    Construction validates every field and raises :class:`GaitParameterError` naming the
    offending field and its allowed range.
    """

    body_velocity: float
    body_height: float
    radius: np.ndarray
    angle_offset: np.ndarray
    step_height: np.ndarray
    duty_factor: np.ndarray
    phase_offset: np.ndarray
    period: float = DEFAULT_PERIOD
    crab_angle: float = DEFAULT_CRAB_ANGLE
    turn_rate: float = 0.0
    archive_index: int = field(default=-1)

    def __post_init__(self) -> None:
        for name in SCALAR_FIELDS:
            object.__setattr__(self, name, _check_scalar(name, getattr(self, name)))
        for name in LEG_FIELDS:
            object.__setattr__(self, name, _check_leg_array(name, getattr(self, name)))
        try:
            object.__setattr__(self, 'archive_index', int(self.archive_index))
        except (TypeError, ValueError):
            raise GaitParameterError(
                'archive_index', f'expected an integer, got {self.archive_index!r}'
            ) from None

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, GaitParameters):
            return NotImplemented
        return (
            all(
                np.array_equal(getattr(self, f), getattr(other, f))
                for f in SCALAR_FIELDS + LEG_FIELDS
            )
            and self.archive_index == other.archive_index
        )

    def replace(self, **changes: Any) -> 'GaitParameters':
        """Return a copy with some fields changed (validated again)."""
        values = self.to_dict()
        values.update(changes)
        return GaitParameters(**values)

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-serialisable dict (lists for per-leg fields)."""
        d: dict[str, Any] = {name: float(getattr(self, name)) for name in SCALAR_FIELDS}
        d.update({name: [float(v) for v in getattr(self, name)] for name in LEG_FIELDS})
        d['archive_index'] = self.archive_index
        return d

    @classmethod
    def from_dict(cls, values: Mapping[str, Any]) -> 'GaitParameters':
        """
        Inverse of :meth:`to_dict`.

        Unknown keys are an error, missing ones too (except period, crab_angle, turn_rate and
        archive_index, which default).
        """
        known = set(SCALAR_FIELDS + LEG_FIELDS + ('archive_index',))
        unknown = set(values) - known
        if unknown:
            raise GaitParameterError(
                sorted(unknown)[0], f'unknown gait field; known fields: {sorted(known)}'
            )
        for name in ('body_velocity', 'body_height') + LEG_FIELDS:
            if name not in values:
                raise GaitParameterError(name, 'missing')
        return cls(**dict(values))


def genotype_fields(genotypes: np.ndarray) -> dict[str, np.ndarray]:
    """
    Scale genotypes (G, 32) or (G, 34) to gait fields.

    body_height and body_velocity (G, 1), the per-leg fields (G, 6); for 34-gene (omni) genotypes
    also crab_angle and turn_rate (G, 1). The single definition of both mappings, used by the
    decoders and by batch computations (e.g. reachability prefilters). No validation.
    """
    g = np.asarray(genotypes, dtype=float)
    legs = g[:, 2:GENOTYPE_SIZE].reshape(-1, N_LEGS, 5)
    lo_off, hi_off = RANGES['angle_offset']
    fields = {
        'body_height': g[:, 0:1] * RANGES['body_height'][1],
        'body_velocity': g[:, 1:2] * RANGES['body_velocity'][1],
        'radius': legs[:, :, 0] * RANGES['radius'][1],
        'angle_offset': lo_off + legs[:, :, 1] * (hi_off - lo_off),
        'step_height': legs[:, :, 2] * RANGES['step_height'][1],
        'phase_offset': legs[:, :, 3],
        'duty_factor': legs[:, :, 4],
    }
    if g.shape[1] == OMNI_GENOTYPE_SIZE:
        lo_c, hi_c = RANGES['crab_angle']
        lo_t, hi_t = OMNI_TURN_RANGE
        crab, turn = g[:, GENOTYPE_SIZE, None], g[:, GENOTYPE_SIZE + 1, None]
        fields['crab_angle'] = lo_c + crab * (hi_c - lo_c)
        fields['turn_rate'] = lo_t + turn * (hi_t - lo_t)
    return fields


def _checked_genes(genotype: Sequence[float] | np.ndarray, size: int) -> np.ndarray:
    g = np.asarray(genotype, dtype=float).reshape(-1)
    if g.size != size:
        raise GaitParameterError('genotype', f'expected {size} genes, got {g.size}')
    bad = ~np.isfinite(g) | (g < 0.0) | (g > 1.0)
    if bad.any():
        i = int(np.argmax(bad))
        raise GaitParameterError(f'genotype[{i}]', f'{g[i]:g} is outside the allowed range [0, 1]')
    return g


def _gait_of_fields(fields: dict[str, np.ndarray], archive_index: int) -> GaitParameters:
    scalars = {
        name: fields[name][0, 0]
        for name in ('body_height', 'body_velocity', 'crab_angle', 'turn_rate')
        if name in fields
    }
    return GaitParameters(
        **scalars, **{name: fields[name][0] for name in LEG_FIELDS}, archive_index=archive_index
    )


def from_genotype(
    genotype: Sequence[float] | np.ndarray, archive_index: int = -1
) -> GaitParameters:
    """
    Scale a 32-number genotype in [0, 1] to gait parameters (mapping GENOTYPE_MAPPING_VERSION).

    Layout (the thesis code's ``reshape``, so thesis maps import unchanged): g[0] body height,
    g[1] body velocity, then per leg 1..6 five genes: radius, angle offset, step height,
    phase offset, duty factor. Period and crab angle are the constants DEFAULT_PERIOD and
    DEFAULT_CRAB_ANGLE.
    """
    g = _checked_genes(genotype, GENOTYPE_SIZE)
    return _gait_of_fields(genotype_fields(g[None, :]), archive_index)


def _leg_genes(params: GaitParameters) -> list[np.ndarray]:
    lo_off, hi_off = RANGES['angle_offset']
    legs = np.stack(
        [
            params.radius / RANGES['radius'][1],
            (params.angle_offset - lo_off) / (hi_off - lo_off),
            params.step_height / RANGES['step_height'][1],
            params.phase_offset,
            params.duty_factor,
        ],
        axis=1,
    )
    head = [
        params.body_height / RANGES['body_height'][1],
        params.body_velocity / RANGES['body_velocity'][1],
    ]
    return [np.asarray(head), legs.reshape(-1)]


def to_genotype(params: GaitParameters) -> np.ndarray:
    """
    Inverse of :func:`from_genotype`.

    Raises if the gait's period, crab angle or turn rate differ from the mapping's constants (such
    a gait has no thesis genotype).
    """
    if (
        not math.isclose(params.period, DEFAULT_PERIOD)
        or not math.isclose(params.crab_angle, DEFAULT_CRAB_ANGLE)
        or params.turn_rate != 0.0
    ):
        raise GaitParameterError(
            'period/crab_angle/turn_rate',
            f'only gaits with period {DEFAULT_PERIOD} s, crab angle {DEFAULT_CRAB_ANGLE:.6f}'
            ' rad and no turn have a genotype',
        )
    return np.concatenate(_leg_genes(params))


# -- the omnidirectional genotype (navigation repertoires) -------------------------------------
#: Version of the omnidirectional mapping: the thesis's 32 genes, then the crab angle over
#: [-pi, pi] and the turn rate over OMNI_TURN_RANGE. Period fixed at DEFAULT_PERIOD.
OMNI_MAPPING_VERSION = 'omni/v1'
OMNI_GENOTYPE_SIZE = GENOTYPE_SIZE + 2  # 34
#: Turn rates a repertoire gait may use [rad/s]: enough to cancel a gait's own drift in heading.
OMNI_TURN_RANGE = (-0.5, 0.5)


def from_omni_genotype(
    genotype: Sequence[float] | np.ndarray, archive_index: int = -1
) -> GaitParameters:
    """Scale a 34-number omni genotype in [0, 1] to gait parameters (OMNI_MAPPING_VERSION)."""
    g = _checked_genes(genotype, OMNI_GENOTYPE_SIZE)
    return _gait_of_fields(genotype_fields(g[None, :]), archive_index)


def to_omni_genotype(params: GaitParameters) -> np.ndarray:
    """Inverse of :func:`from_omni_genotype`; raises for a period or turn rate it cannot hold."""
    lo_t, hi_t = OMNI_TURN_RANGE
    if not math.isclose(params.period, DEFAULT_PERIOD) or not lo_t <= params.turn_rate <= hi_t:
        raise GaitParameterError(
            'period/turn_rate',
            f'an omni genotype holds period {DEFAULT_PERIOD} s and turn rates in'
            f' [{lo_t:g}, {hi_t:g}] rad/s',
        )
    lo_c, hi_c = RANGES['crab_angle']
    extra = [(params.crab_angle - lo_c) / (hi_c - lo_c), (params.turn_rate - lo_t) / (hi_t - lo_t)]
    return np.concatenate(_leg_genes(params) + [np.asarray(extra)])


@dataclass(frozen=True)
class GenotypeMapping:
    """One genotype <-> gait mapping, named by the version string that archives record."""

    version: str
    size: int
    decode: Callable[..., GaitParameters]  # (genes, archive_index=-1) -> gait
    encode: Callable[[GaitParameters], np.ndarray]


MAPPINGS: dict[str, GenotypeMapping] = {
    GENOTYPE_MAPPING_VERSION: GenotypeMapping(
        GENOTYPE_MAPPING_VERSION, GENOTYPE_SIZE, from_genotype, to_genotype
    ),
    OMNI_MAPPING_VERSION: GenotypeMapping(
        OMNI_MAPPING_VERSION, OMNI_GENOTYPE_SIZE, from_omni_genotype, to_omni_genotype
    ),
}


def genotype_mapping(version: str) -> GenotypeMapping:
    """Return the mapping an archive names; ValueError lists the known ones."""
    try:
        return MAPPINGS[version]
    except (KeyError, TypeError):
        raise ValueError(
            f'unknown genotype mapping {version!r}; known: {", ".join(MAPPINGS)}'
        ) from None
