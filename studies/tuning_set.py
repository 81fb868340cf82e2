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
The tuning set (issue 19): damage that is not the reported experiment's lifted legs.

Settings are chosen on these cases (with the seed-2 map, ``studies/adaptation/make_tuning_map.sh``), never on
S1-S4's lifted legs, which are reported once.
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
