# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Failure scenarios S0-S4 and failed-leg validation (hexapod_sim.scenarios, simulator)."""

from __future__ import annotations

from hexapod_sim import all_scenarios, scenario, validate_failed_legs
import pytest


def test_scenario_orientation_counts_and_sets():
    counts = {name: len(v) for name, v in all_scenarios().items()}
    assert counts == {'S0': 1, 'S1': 6, 'S2': 3, 'S3': 6, 'S4': 6}
    assert scenario('S2') == [(1, 4), (2, 5), (3, 6)]
    assert (1, 6) in scenario('S4') and (1, 2) in scenario('S4')
    assert (1, 5) in scenario('S3') and (2, 4) in scenario('S3')
    with pytest.raises(ValueError, match="unknown failure scenario 'S9'"):
        scenario('S9')


@pytest.mark.parametrize(
    'legs,match',
    [
        ([7], 'leg 7 does not exist'),
        ([0], 'leg 0 does not exist'),
        ([1, 2, 3], 'at most 2 legs'),
        (['a'], 'integers 1..6'),
        ([True], 'integers 1..6'),
    ],
)
def test_bad_failed_legs_are_refused_with_a_reason(legs, match):
    with pytest.raises(ValueError, match=match):
        validate_failed_legs(legs)
    assert validate_failed_legs([3, 1, 3]) == (1, 3)
