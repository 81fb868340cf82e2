# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Reference gaits: tripod, wave, quadruped (thesis tables 3.11-3.13) and the control gait.

The tables give the per-leg parameters only (radius 0.15 m, offset 0, step height 0.06 m,
phase offsets and duty factors). Body speed and height are chosen here so that all three have
the control gait's stride (v * T * beta = 0.15 m) at the control gait's body height (0.14 m):
the same foot path, different footfall timing. The control gait (thesis 5.2.3) is the tripod
at 0.3 m/s commanded and 140 mm body height, i.e. the tripod preset.

Table 3.12 lists a duty factor of 1/6 for the wave gait; a wave gait swings one leg at a time
(five legs in stance), which needs beta = 5/6 (as the thesis code uses), so 5/6 is used.
All presets walk along DEFAULT_CRAB_ANGLE, the map gaits' direction, so speeds compare.
"""

from __future__ import annotations

from hexapod_gait.parameters import GaitParameters

STRIDE = 0.15  # m
BODY_HEIGHT = 0.14  # m


def _preset(phase: list[float], duty: float) -> GaitParameters:
    return GaitParameters(
        body_velocity=STRIDE / duty,
        body_height=BODY_HEIGHT,
        radius=[0.15] * 6,
        angle_offset=[0.0] * 6,
        step_height=[0.06] * 6,
        duty_factor=[duty] * 6,
        phase_offset=phase,
    )


def tripod() -> GaitParameters:
    """Table 3.11: legs {1,3,5} and {2,4,6} alternate, beta = 1/2 (0.3 m/s)."""
    return _preset([0.0, 0.5, 0.0, 0.5, 0.0, 0.5], 0.5)


def wave() -> GaitParameters:
    """Table 3.12: one leg swings at a time, in the order 1..6, beta = 5/6 (0.18 m/s)."""
    return _preset([i / 6 for i in range(6)], 5 / 6)


def quadruped() -> GaitParameters:
    """Table 3.13: legs {1,4}, {2,5}, {3,6} swing in turn, beta = 2/3 (0.225 m/s)."""
    return _preset([0.0, 1 / 3, 2 / 3, 0.0, 1 / 3, 2 / 3], 2 / 3)


def control() -> GaitParameters:
    """Return the thesis's control gait (5.2.3): tripod, 0.3 m/s commanded, 140 mm body height."""
    return tripod()


PRESETS = {'tripod': tripod, 'wave': wave, 'quadruped': quadruped, 'control': control}

#: How high the checked leg's foot lifts in :func:`leg_check` [m].
LEG_CHECK_LIFT = 0.08


def leg_check(leg: int) -> GaitParameters:
    """
    Return a gait that stands still and lifts only URDF leg ``leg``'s foot, once a second.

    Walked on the robot (``leg_check``), it shows which physical leg the URDF's leg ``leg`` is:
    the check of the bridge's ``leg_map`` before any trial. The other five feet stay on the
    ground (duty factor 1, no step height); no leg strides (body velocity 0).
    """
    if not 1 <= leg <= 6:
        raise ValueError(f'leg must be 1..6, got {leg}')
    lifted = [i == leg - 1 for i in range(6)]
    return GaitParameters(
        body_velocity=0.0,
        body_height=BODY_HEIGHT,
        radius=[0.15] * 6,
        angle_offset=[0.0] * 6,
        step_height=[LEG_CHECK_LIFT if up else 0.0 for up in lifted],
        duty_factor=[0.5 if up else 1.0 for up in lifted],
        phase_offset=[0.0] * 6,
        period=1.0,
        crab_angle=0.0,
    )


def preset(name: str) -> GaitParameters:
    """Return a preset by name; ValueError lists the known names."""
    try:
        return PRESETS[name]()
    except KeyError:
        raise ValueError(f'unknown gait preset {name!r}; known: {", ".join(PRESETS)}') from None


def standing_gait() -> GaitParameters:
    """Return the gait that stands still where the robot is (the control tripod's stance)."""
    return preset('control').replace(body_velocity=0.0, step_height=[0.0] * 6)
