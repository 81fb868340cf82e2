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
