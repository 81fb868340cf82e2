# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Failure scenarios of thesis 5.1.2, generated from leg adjacency (legs 1..6 on a ring): S0 none.

S1 one leg (6 orientations); S2 two opposite legs (3); S3 two legs separated by one (6); S4 two
adjacent legs (6).
"""

from __future__ import annotations

from itertools import combinations

from hexapod_description import N_LEGS

SCENARIO_NAMES = ('S0', 'S1', 'S2', 'S3', 'S4')


def _ring_distance(a: int, b: int) -> int:
    d = abs(a - b) % N_LEGS
    return min(d, N_LEGS - d)


def scenario(name: str) -> list[tuple[int, ...]]:
    """All orientations (sets of failed legs, 1-based) of a failure scenario."""
    if name == 'S0':
        return [()]
    if name == 'S1':
        return [(leg,) for leg in range(1, N_LEGS + 1)]
    # S2: ring distance 3 (opposite), S3: 2 (one leg between), S4: 1 (adjacent)
    distance = {'S2': 3, 'S3': 2, 'S4': 1}.get(name)
    if distance is None:
        raise ValueError(f'unknown failure scenario {name!r}; known: {", ".join(SCENARIO_NAMES)}')
    return [
        pair for pair in combinations(range(1, N_LEGS + 1), 2) if _ring_distance(*pair) == distance
    ]


def all_scenarios() -> dict[str, list[tuple[int, ...]]]:
    """Every scenario's orientations, S0-S4."""
    return {name: scenario(name) for name in SCENARIO_NAMES}
