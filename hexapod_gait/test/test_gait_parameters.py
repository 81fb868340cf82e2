# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Validation and the genotype mapping."""

from __future__ import annotations

import math

from hexapod_gait import (
    DEFAULT_CRAB_ANGLE,
    from_genotype,
    GaitParameterError,
    GaitParameters,
    GENOTYPE_SIZE,
    preset,
    to_genotype,
)
import numpy as np
import pytest


def valid(**changes):
    return preset('tripod').replace(**changes)


@pytest.mark.parametrize(
    'field,value,match',
    [
        ('body_velocity', 0.6, r'body_velocity: 0.6 is outside the allowed range \[0, 0.5\] m/s'),
        ('body_velocity', float('nan'), r'body_velocity: must be finite'),
        ('body_height', float('inf'), r'body_height: must be finite'),
        ('body_height', -0.01, r'body_height: .*\[0, 0.2\] m'),
        ('period', 0.0, r'period: .*\[0.1, 10\] s'),
        ('crab_angle', 4.0, r'crab_angle'),
        ('radius', [0.1] * 5, r'radius: expected 6 values'),
        (
            'radius',
            [0.1, 0.1, 0.31, 0.1, 0.1, 0.1],
            r'radius\[leg 3\]: 0.31 is outside the allowed range \[0, 0.3\] m',
        ),
        ('angle_offset', [0, 0, 0, 0, 0, 2.0], r'angle_offset\[leg 6\]'),
        ('step_height', [0, 0, 0, float('nan'), 0, 0], r'step_height\[leg 4\]'),
        ('duty_factor', [1.2] * 6, r'duty_factor\[leg 1\]: 1.2 .*\[0, 1\]'),
        ('phase_offset', [-0.1] * 6, r'phase_offset\[leg 1\]'),
        ('body_velocity', 'fast', r'body_velocity: expected a number'),
    ],
)
def test_invalid_values_name_the_field_and_range(field, value, match):
    with pytest.raises(GaitParameterError, match=match) as info:
        valid(**{field: value})
    assert info.value.field.startswith(field)


def test_dict_round_trip_and_unknown_fields():
    g = valid(archive_index=17)
    assert GaitParameters.from_dict(g.to_dict()) == g
    with pytest.raises(GaitParameterError, match='unknown gait field'):
        GaitParameters.from_dict({**g.to_dict(), 'speed': 1})
    d = g.to_dict()
    del d['radius']
    with pytest.raises(GaitParameterError, match='radius: missing'):
        GaitParameters.from_dict(d)


def test_parameters_are_immutable():
    g = valid()
    with pytest.raises(Exception):
        g.radius[0] = 1.0
    with pytest.raises(Exception):
        g.body_height = 0.1


def test_genotype_round_trip():
    rng = np.random.default_rng(7)
    for _ in range(200):
        genes = rng.random(GENOTYPE_SIZE)
        np.testing.assert_allclose(to_genotype(from_genotype(genes)), genes, atol=1e-12)
    for edge in (np.zeros(GENOTYPE_SIZE), np.ones(GENOTYPE_SIZE)):
        np.testing.assert_allclose(to_genotype(from_genotype(edge)), edge, atol=1e-12)


def test_genotype_layout_matches_the_thesis_code():
    genes = np.zeros(GENOTYPE_SIZE)
    genes[0], genes[1] = 0.7, 0.4  # body height, body velocity
    leg3 = slice(2 + 5 * 2, 2 + 5 * 3)
    genes[leg3] = [0.5, 0.5, 0.25, 0.1, 0.6]
    g = from_genotype(genes)
    assert g.body_height == pytest.approx(0.14) and g.body_velocity == pytest.approx(0.2)
    assert g.radius[2] == pytest.approx(0.15) and g.angle_offset[2] == pytest.approx(0.0)
    assert g.step_height[2] == pytest.approx(0.05)
    assert g.phase_offset[2] == pytest.approx(0.1) and g.duty_factor[2] == pytest.approx(0.6)
    assert g.period == 1.0 and g.crab_angle == pytest.approx(-math.pi / 6) == DEFAULT_CRAB_ANGLE


@pytest.mark.parametrize(
    'genes,match',
    [
        (np.zeros(31), 'expected 32 genes'),
        (np.r_[np.zeros(31), 1.5], r'genotype\[31\]: 1.5 is outside'),
        (np.r_[np.nan, np.zeros(31)], r'genotype\[0\]'),
    ],
)
def test_bad_genotypes(genes, match):
    with pytest.raises(GaitParameterError, match=match):
        from_genotype(genes)


def test_gait_without_genotype():
    with pytest.raises(GaitParameterError, match='have a genotype'):
        to_genotype(valid(crab_angle=0.0))
