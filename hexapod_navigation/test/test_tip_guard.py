# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The tip guard and the tilt the believed damage predicts (issue 31: steps that tip over)."""

from dataclasses import replace
import json
import math
from pathlib import Path

from hexapod_adapt.mapping.simulation import worker_simulator
from hexapod_gait.parameters import from_omni_genotype
from hexapod_navigation.core.config import NavigationConfig
from hexapod_navigation.core.episode import BodyFailure, GUARD_STAND_S, run_episode, SimBody
from hexapod_navigation.core.geometry import Pose2D
from hexapod_navigation.core.loading import load_navigation
from hexapod_navigation.core.planner import RepertoirePolicy
from hexapod_navigation.core.repertoire import shipped_repertoire
from hexapod_navigation.core.specialists import shipped_specialists
from hexapod_navigation.core.step_bank import shipped_step_bank
from hexapod_sim import create_simulator, SimConfig
from hexapod_sim.damage import Damage
from hexapod_sim.evaluation import evaluate_displacements
import numpy as np
import pytest

#: legs 2 and 6 without their tibias: damage the bank does not hold, on which a specialist tips
LOST_TIBIAS = Damage.of('no_tibia', (2, 6))


@pytest.fixture(scope='module')
def navigation():
    data = load_navigation(shipped_repertoire(), shipped_step_bank(), shipped_specialists())
    assert data.specialists > 0, data.no_specialists
    return data


@pytest.fixture(scope='module')
def tipping(navigation):
    """
    Return a step that tips the robot over under LOST_TIBIAS (data/tipping_step.json).

    A reverse-crab variant of an older map's fastest gait with a locked leg 2: the kind of
    specialist that tipped the robot over in the twelfth tuning round. Checked to tip first.
    """
    frozen = json.loads((Path(__file__).parent / 'data' / 'tipping_step.json').read_text())
    genes = np.array([frozen['omni_genotype']])
    (move,) = evaluate_displacements(
        genes,
        worker_simulator('mujoco'),
        navigation.repertoire.step_duration,
        collisions_fatal=False,
        failed_legs=LOST_TIBIAS,
        decode=from_omni_genotype,
    )
    assert move.valid and move.peak_tilt > math.radians(60.0), 'the frozen step no longer tips'
    return from_omni_genotype(genes[0])


@pytest.fixture
def sim():
    with create_simulator(SimConfig(engine='mujoco')) as s:
        s.set_damage(LOST_TIBIAS)
        yield s


def test_the_guard_stops_a_step_that_would_tip_the_robot_over_and_the_robot_stands(tipping, sim):
    body = SimBody(sim)
    body.start()
    with pytest.raises(BodyFailure, match='tipped over'):
        body.walk(tipping, 2.0, lambda p: False)
    guarded = SimBody(sim, tip_guard=0.52)
    guarded.start()
    out = guarded.walk(tipping, 2.0, lambda p: False)
    assert out.tilted and not out.completed
    assert GUARD_STAND_S < out.elapsed < 2.0 + GUARD_STAND_S  # stopped early, then stood
    roll, pitch, _ = sim.base_euler()
    assert max(abs(roll), abs(pitch)) < 0.1  # upright again
    assert guarded.playing is not tipping


def test_a_step_that_stays_below_the_guard_is_walked_whole(sim):
    from hexapod_gait import preset

    sim.set_damage(Damage())
    body = SimBody(sim, tip_guard=0.52)
    body.start()
    out = body.walk(preset('control'), 2.0, lambda p: False)
    assert out.completed and not out.tilted and out.elapsed == pytest.approx(2.0)


def test_a_step_that_tilted_past_the_guard_is_never_taken_again(navigation, sim):
    config = NavigationConfig(tip_guard=0.02, time_limit=12.0)  # every step trips it
    policy = RepertoirePolicy.with_bank(navigation.repertoire, config, navigation.bank)
    body = SimBody(sim, tip_guard=config.tip_guard)
    body.start()
    taken = []
    walk = body.walk

    def logged(gait, duration, stop):
        out = walk(gait, duration, stop)
        taken.append((chosen[-1], out.tilted))
        return out

    chosen = []
    plan = policy.next_step

    def choose(*args, **kwargs):
        step = plan(*args, **kwargs)
        chosen.append(step.index if step.tripod < 0 else ('tripod', step.tripod))
        return step

    body.walk, policy.next_step = logged, choose
    run_episode(body, policy, (2.0, 0.0), config)
    tilted = [k for k, t in taken if t]
    assert len(tilted) >= 2
    assert len(set(tilted)) == len(tilted)  # none taken twice
    for k in tilted:
        if not isinstance(k, tuple):
            assert not policy.allowed[k]


def test_specialists_the_believed_damage_tilts_past_the_limit_are_held_back(navigation):
    bank = navigation.bank
    # the robot reported legs 2 and 6 dead (it believes it): a damage the bank holds
    told = NavigationConfig(prior_reported=0.999, tripod_option=False)
    reported = Damage.lifted((2, 6))
    goals = [
        (2.0 * math.cos(a), 2.0 * math.sin(a))
        for a in np.random.default_rng(0).uniform(-math.pi, math.pi, 200)
    ]

    def chosen(config: NavigationConfig) -> set[int]:
        policy = RepertoirePolicy.with_bank(navigation.repertoire, config, bank, reported)
        return {policy.next_step(Pose2D(0.0, 0.0, 0.0), g).index for g in goals}

    free = RepertoirePolicy.with_bank(navigation.repertoire, told, bank, reported)
    end = 1 + len(bank)
    w = free.gp.weights[1:end]
    expected = np.nansum(w[:, None] * bank.tilt, axis=0) / w.sum()
    measured = ~np.isnan(bank.tilt).all(axis=0)  # the specialists
    assert measured.sum() == navigation.specialists
    taken = [i for i in chosen(told) if measured[i]]
    assert taken, 'no specialist is ever the best step here: the test shows nothing'
    limit = 0.99 * max(expected[i] for i in taken)  # holds back the most tilted one taken
    held = chosen(replace(told, expected_tilt_limit=limit))
    assert not any(expected[i] > limit for i in held)
    assert held  # it still walks: the repertoire's steps are never held back


def test_the_tilt_settings_are_checked():
    for name in ('tip_guard', 'expected_tilt_limit'):
        with pytest.raises(ValueError, match=f'{name} must be in'):
            NavigationConfig(**{name: 0.0})
        with pytest.raises(ValueError, match=f'{name} must be in'):
            NavigationConfig(**{name: 4.0})
