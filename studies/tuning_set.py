# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The tuning set (issue 19): damage that is not the reported experiment's lifted legs.

Settings are chosen on these cases (with the seed-2 map,
``studies/adaptation/make_tuning_map.sh``), never on S1-S4's lifted legs, which are reported once.
"""

from __future__ import annotations

from hexapod_sim.damage import Damage
from hexapod_sim.scenarios import scenario

TUNING_KINDS = ('locked', 'weak', 'no_tibia')
#: Every tuning kind on each single leg and each pair of legs (the S2-S4 pairs): 3 x 21 cases.
TUNING_DAMAGES: tuple[Damage, ...] = tuple(
    Damage.of(kind, legs)
    for kind in TUNING_KINDS
    for name in ('S1', 'S2', 'S3', 'S4')
    for legs in scenario(name)
)
#: Trial budget of a tuning run: the product's, 24 trials (2 minutes of 5 s trials).
TUNING_MAX_TRIALS = 24
