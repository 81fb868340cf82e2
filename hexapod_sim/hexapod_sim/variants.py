# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Physics variants: the robot as each physics we are unsure of might have it (issue 66).

The robot is none of our engines. A map whose stored speed is what a gait walks across variants
of the physics (friction, servo stiffness and strength, control latency, masses, floor
stiffness) is less likely to keep gaits that are fast only in one model. :data:`RANGES` are
those of studies/robust_speed/README.md, written before its runs, with their reasons. Each
variant draws every quantity independently and uniformly (the compliance slope log-uniformly),
from a seed. Variants are MuJoCo settings plus the floor's friction (:func:`variant_config`).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, replace
import math
from typing import Any

from hexapod_sim.simulator import SimConfig
import numpy as np

#: (low, high) of each quantity (studies/robust_speed/README.md, "The variants").
RANGES: dict[str, tuple[float, float]] = {
    'friction': (0.5, 1.2),  # foot-floor
    'compliance_slope': (16.0, 64.0),  # RX position units, drawn log-uniformly
    'effort_scale': (0.8, 1.1),  # stall torque (battery sag to the rated voltage)
    'speed_scale': (0.8, 1.1),  # no-load speed (back-EMF)
    'latency_rows': (0, 4),  # rows of 240 Hz, an integer
    'base_mass_scale': (0.9, 1.1),
    'coxa_mass_scale': (0.95, 1.05),
    'femur_mass_scale': (0.95, 1.05),
    'tibia_mass_scale': (0.95, 1.05),
    'contact_timeconst': (0.01, 0.04),  # s: a hard floor to a carpet
}


@dataclass(frozen=True)
class PhysicsVariant:
    """One draw of the physics we are unsure of (the fields of :data:`RANGES`)."""

    friction: float
    compliance_slope: float
    effort_scale: float
    speed_scale: float
    latency_rows: int
    base_mass_scale: float
    coxa_mass_scale: float
    femur_mass_scale: float
    tibia_mass_scale: float
    contact_timeconst: float

    def as_dict(self) -> dict[str, Any]:
        """Return the variant as plain data (recorded in a map's fingerprint)."""
        return asdict(self)


def draw_variants(count: int, seed: int) -> tuple[PhysicsVariant, ...]:
    """Return ``count`` variants drawn from ``seed`` (the same seed, the same variants)."""
    if not (isinstance(count, int) and 1 <= count <= 256):
        raise ValueError(f'variants must be an integer in [1, 256], got {count!r}')
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        values: dict[str, Any] = {}
        for name, (low, high) in RANGES.items():
            if name == 'compliance_slope':
                values[name] = float(math.exp(rng.uniform(math.log(low), math.log(high))))
            elif name == 'latency_rows':
                values[name] = int(rng.integers(int(low), int(high) + 1))
            else:
                values[name] = float(rng.uniform(low, high))
        out.append(PhysicsVariant(**values))
    return tuple(out)


def variant_config(config: SimConfig, variant: PhysicsVariant) -> SimConfig:
    """Return ``config`` (a MuJoCo one) with ``variant``'s physics."""
    if config.engine != 'mujoco':
        raise ValueError(f'physics variants are MuJoCo settings; {config.engine} has none')
    fields = variant.as_dict()
    friction = fields.pop('friction')
    return replace(config, friction=friction, mujoco=replace(config.engine_settings(), **fields))
