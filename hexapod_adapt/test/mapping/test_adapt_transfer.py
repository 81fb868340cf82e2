# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""A map's gaits on another engine: the fastest's speed and tip-overs, the ranking's agreement."""

import json
from pathlib import Path

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.mapping.transfer import ranked_gaits, transfer_figures
from hexapod_gait import preset, to_genotype
from hexapod_sim import create_simulator, evaluate_gaits
import numpy as np
import pytest

#: A gait that ends on its back on PyBullet, intact and with leg 1 lifted.
FALLING = Path(__file__).resolve().parents[1] / 'data' / 'falling_gaits.json'
TIPPER = json.loads(FALLING.read_text())['tips_intact_and_leg_1_lifted']['genotype']


def _archive():
    genes = [to_genotype(preset(name)) for name in ('control', 'tripod', 'wave', 'quadruped')]
    genes.append(np.array(TIPPER))
    desc = np.eye(5, 6) * 0.5 + 0.25
    # the map ranks the tipper first, then the presets as they walk
    return Archive(desc, np.array([1.4, 1.3, 0.8, 1.1, 3.0]), desc, np.array(genes))


def test_ranked_gaits_are_the_fastest_then_others_at_random_without_repeats():
    a = _archive()
    niches = ranked_gaits(a, fastest=2, random=2, seed=0)
    assert niches[:2].tolist() == [4, 0]
    assert len(set(niches.tolist())) == 4 and set(niches[2:]) <= {1, 2, 3}
    assert ranked_gaits(a, 2, 2, seed=0).tolist() == niches.tolist()  # seeded


def test_transfer_figures_count_the_tipped_and_rank_against_the_engine():
    a = _archive()
    with create_simulator() as sim:
        figures = transfer_figures(a, sim, top=2, fastest=2, random=3)
        walked = evaluate_gaits(
            list(a.genotypes[[4, 0]]), sim, collisions_fatal=False, failed_legs=(),
            record_tilt=True,
        )  # fmt: skip
    assert figures.engine == 'pybullet' and figures.top == 2 and figures.ranked == 5
    tipped = sum(r.peak_tilt > np.radians(60) for r in walked)
    assert figures.top_tipped == tipped
    assert figures.top_speed_median == pytest.approx(np.median([r.speed for r in walked]))
    assert figures.top_map_speed_median == pytest.approx(np.median([3.0, 1.4]) / 5.0)
    assert -1.0 <= figures.spearman <= 1.0
    with pytest.raises(ValueError, match='among'):
        transfer_figures(a, sim, top=3, fastest=2)
