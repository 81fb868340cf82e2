# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The navigation repertoire: its map kind, its generation, and its evaluation."""

import math

from hexapod_adapt.mapping.archive import Archive, ArchiveError, load_archive
from hexapod_adapt.mapping.generate import generate_map, GenerateConfig
from hexapod_adapt.mapping.steps import (
    from_descriptor,
    SimulateSteps,
    STEP_DURATION,
    to_descriptor,
)
from hexapod_gait import preset
from hexapod_gait.parameters import to_omni_genotype
from hexapod_navigation.core.repertoire import Repertoire
import numpy as np
import pytest


def test_descriptor_scaling_round_trips_and_clips_at_the_reach():
    xy = np.array([[0.3, -0.8], [0.0, 0.0], [-0.99, 1.0]])
    np.testing.assert_allclose(from_descriptor(to_descriptor(xy[:, 0], xy[:, 1])), xy)
    assert to_descriptor(9.0, -9.0).tolist() == [1.0, 0.0]


def test_a_step_is_measured_in_the_start_frame_and_scored_by_heading_kept():
    straight = preset('tripod').replace(crab_angle=math.pi / 2)
    turning = straight.replace(turn_rate=0.3)
    genes = np.array([to_omni_genotype(straight), to_omni_genotype(turning)])
    a, b = SimulateSteps('mujoco')(genes)
    assert a.valid and b.valid
    # the tripod walks 0.3 m/s: sideways (+y), heading kept
    assert a.displacement.y == pytest.approx(0.3 * STEP_DURATION, rel=0.1)
    assert abs(a.displacement.x) < 0.05 and a.fitness > -0.05
    # the commanded turn shows as heading change, and costs fitness
    assert b.displacement.yaw == pytest.approx(0.3 * STEP_DURATION, rel=0.1)
    assert b.fitness == pytest.approx(-abs(b.displacement.yaw)) and b.fitness < a.fitness
    np.testing.assert_allclose(a.descriptor, to_descriptor(a.displacement.x, a.displacement.y))


def test_a_repertoire_may_keep_only_gaits_with_enough_feet_down():
    from hexapod_adapt.mapping.steps import gait_min_stance, repertoire_fingerprint

    control = preset('control')  # a tripod: three feet down at every instant
    airborne = control.replace(duty_factor=[0.3] * 6)  # every foot up at some instant
    assert gait_min_stance(control) == 3 and gait_min_stance(airborne) < 3
    genes = np.array([to_omni_genotype(airborne), to_omni_genotype(control)])
    lifted, kept = SimulateSteps('mujoco', min_stance_legs=3)(genes)
    assert not lifted.valid and 'fewer than 3 feet' in lifted.displacement.reason
    assert lifted.displacement.duration == 0.0  # refused without being simulated
    assert kept.valid and kept.displacement.x > 0.3
    # the same gait without the rule walks (it is a gait, just not a stable one)
    assert SimulateSteps('mujoco')(genes[:1])[0].displacement.duration > 0
    # the rule is part of the repertoire's fingerprint; without it the print is as before
    assert repertoire_fingerprint('mujoco', 3)['min_stance_legs'] == 3
    assert 'min_stance_legs' not in repertoire_fingerprint('mujoco')
    with pytest.raises(ValueError, match='min_stance_legs must be 0..6'):
        SimulateSteps('mujoco', min_stance_legs=7)
    with pytest.raises(ValueError, match='navigation repertoires only'):
        GenerateConfig(out='x.npz', min_stance_legs=3)


@pytest.mark.slow
def test_generate_map_makes_a_navigation_repertoire_that_resumes_exactly(tmp_path):
    small = {'niches': 40, 'seed': 2, 'lag': 16, 'checkpoint_every': 1.0, 'log_every': 0.5}
    small['kind'] = 'navigation'
    full = generate_map(
        GenerateConfig(out=tmp_path / 'a' / 'nav.npz', evaluations=160, with_presets=True, **small)
    )
    assert full.kind.name == 'navigation' and full.genotypes.shape == (40, 34)
    assert (tmp_path / 'a' / 'centroids_40_2.dat').is_file()
    # the presets walk in eight directions: the repertoire reaches every quadrant
    rep = Repertoire.from_archive(load_archive(tmp_path / 'a' / 'nav.npz'))
    quadrants = {(bool(x > 0), bool(y > 0)) for x, y in rep.moves if math.hypot(x, y) > 0.3}
    assert len(quadrants) == 4
    assert np.all(rep.heading_error >= 0) and rep.step_duration == STEP_DURATION
    # half now, the rest after a resume: the same repertoire
    out = tmp_path / 'b' / 'nav.npz'
    generate_map(GenerateConfig(out=out, evaluations=80, with_presets=True, **small))
    resumed = generate_map(
        GenerateConfig(out=out, evaluations=160, with_presets=True, resume=True, **small)
    )
    np.testing.assert_array_equal(resumed.genotypes, full.genotypes)
    # a gait map cannot resume it: its preset genotypes differ, and so would its simulation
    with pytest.raises(ArchiveError, match='initial 32 genotypes, not 4 genotypes'):
        generate_map(
            GenerateConfig(
                out=out, evaluations=200, seed=2, lag=16, with_presets=True, resume=True
            )
        )


def test_a_gait_map_is_not_a_repertoire_and_kinds_are_checked():
    gait_map = Archive.empty(np.random.default_rng(0).random((5, 6)))
    with pytest.raises(ArchiveError, match='not a navigation repertoire'):
        Repertoire.from_archive(gait_map)
    with pytest.raises(ArchiveError, match='centroids of a navigation map must be'):
        Archive.empty(np.zeros((5, 6)), {'kind': 'navigation'})
    with pytest.raises(ArchiveError, match="unknown map kind 'teleport'"):
        Archive.empty(np.zeros((5, 2)), {'kind': 'teleport'})


def test_a_repertoire_file_with_the_wrong_genotype_mapping_is_refused(tmp_path):
    nav = Archive.empty(np.random.default_rng(0).random((5, 2)), {'kind': 'navigation'})
    nav.metadata['genotype_mapping'] = 'thesis-4.1/v1'
    nav.save(tmp_path / 'nav.npz')
    with pytest.raises(ArchiveError, match='a navigation map holds omni/v1 genotypes'):
        load_archive(tmp_path / 'nav.npz')
