# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Simulator library, both engines.

Determinism, measured footfall, failures, collisions, scenarios, settings.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

from hexapod_gait import from_genotype, preset
from hexapod_gait.trajectory import build_joint_table
from hexapod_sim import (
    create_simulator,
    ENGINES,
    evaluate_gait,
    evaluate_gaits,
    FAILURE_POSE,
    SimConfig,
)
from hexapod_sim.engine_settings import MujocoSettings, PyBulletSettings
from hexapod_sim.sampling import random_reachable_genotypes
import numpy as np
import pytest


@pytest.fixture(scope='module', params=ENGINES)
def sim(request):
    with create_simulator(SimConfig(engine=request.param)) as s:
        yield s


def _fingerprint(result) -> dict:
    return {
        'fitness': result.fitness.hex(),
        'descriptor': [float(v).hex() for v in result.descriptor],
        'valid': result.valid,
        'reason': result.reason,
    }


FRESH_PROCESS = """
import json, sys
import numpy as np
from hexapod_sim import SimConfig, create_simulator, evaluate_gait
genes = np.array(json.loads(sys.argv[1]))
with create_simulator(SimConfig(engine=sys.argv[2])) as sim:
    r = evaluate_gait(genes, sim, collisions_fatal=False)
print(json.dumps({"fitness": r.fitness.hex(), "descriptor": [float(v).hex() for v in r.descriptor],
                  "valid": r.valid, "reason": r.reason}))
"""


@pytest.mark.slow
def test_deterministic_fresh_process_vs_reused_simulator(sim):
    genotypes = random_reachable_genotypes(3, seed=4)
    # warm the reused simulator with other gaits (and a failure) first
    evaluate_gait(preset('wave'), sim, failed_legs=[2])
    sim.set_failed_legs([])
    evaluate_gait(preset('quadruped'), sim)
    for genes in genotypes:
        reused = _fingerprint(evaluate_gait(genes, sim, collisions_fatal=False))
        again = _fingerprint(evaluate_gait(genes, sim, collisions_fatal=False))
        out = subprocess.run(
            [sys.executable, '-c', FRESH_PROCESS, json.dumps(genes.tolist()), sim.engine],
            check=True,
            capture_output=True,
            text=True,
            env=dict(os.environ),
        ).stdout
        fresh = json.loads(out.strip().splitlines()[-1])
        assert reused == again == fresh


def test_measured_tripod_footfall_alternates_the_two_tripods(sim):
    result = evaluate_gait(preset('tripod'), sim, record_contacts=True)
    contacts = result.contacts[240:].astype(float)  # skip the first cycle (start-up transient)
    corr = np.corrcoef(contacts.T)
    tripods = ([0, 2, 4], [1, 3, 5])
    within = [corr[i, j] for t in tripods for i in t for j in t if i < j]
    across = [corr[i, j] for i in tripods[0] for j in tripods[1]]
    # feet of a tripod go down together; the two tripods alternate (thesis fig. 3.11). Contacts
    # chatter within a stance phase, so compare correlations and majority votes, not "all down".
    assert min(within) > 0.4 and max(across) < -0.4, (within, across)
    a_down = contacts[:, tripods[0]].sum(axis=1) >= 2
    b_down = contacts[:, tripods[1]].sum(axis=1) >= 2
    # only brief overlaps at the switch: a tripod gait whose feet are down a fraction beta of the
    # time has both tripods down about 2 (beta - 1/2) of it (MuJoCo's compliant servos and soft
    # contacts measure beta ~0.57, PyBullet ~0.50), plus the switch itself: PyBullet's feet on the
    # thesis simulator's friction (0.49 between foot and ground) measured 0.109 at beta 0.50
    beta = float(result.descriptor.mean())
    assert np.mean(a_down & b_down) < max(0.0, 2 * (beta - 0.5)) + 0.15
    assert a_down.mean() > 0.4 and b_down.mean() > 0.4
    assert result.valid and result.speed > 0.2


@pytest.mark.parametrize(
    'gait,legs',
    [
        ('wave', (1,)),
        ('wave', (4,)),
        ('quadruped', (3,)),
        ('quadruped', (2, 5)),
        ('wave', (1, 3)),
        ('quadruped', (2, 4)),
    ],
)
def test_failed_leg_holds_its_pose_and_never_touches_the_ground(sim, gait, legs):
    result = evaluate_gait(
        preset(gait), sim, failed_legs=legs, collisions_fatal=False, record_contacts=True
    )
    q, _, _ = sim.joint_states()
    # On DART, with legs 2 and 4 lifted, the quadruped's stance legs reach their servos' stall
    # torque and the body sinks (0.14 to 0.08 m) until the folded leg 2 grazes the floor: it
    # still holds its pose (checked below). studies/engines/README.md, "Where the engines differ".
    sinks = sim.engine == 'dart' and (gait, legs) == ('quadruped', (2, 4))
    for leg in legs:
        if not sinks:
            assert result.contacts[:, leg - 1].sum() == 0, f'failed leg {leg} touched the ground'
            assert result.descriptor[leg - 1] == 0.0
        # the grazing leg is pushed by the floor: 2.6 degrees at the tibia (DART, friction 1)
        np.testing.assert_allclose(
            q[slice(3 * (leg - 1), 3 * leg)], FAILURE_POSE, atol=np.radians(5 if sinks else 2)
        )
    sim.set_failed_legs([])


def test_base_dragging_gait_is_flagged(sim):
    low = preset('tripod').replace(body_height=0.04, body_velocity=0.1, step_height=[0.02] * 6)
    result = evaluate_gait(low, sim, collisions_fatal=True)
    assert not result.valid and result.fitness == 0.0 and not result.descriptor.any()
    assert 'base_link touched the ground' in result.reason
    relaxed = evaluate_gait(low, sim, collisions_fatal=False)
    assert relaxed.valid and relaxed.collision_steps > 0


def test_self_colliding_gait_is_flagged(sim):
    # legs 1 and 2 turn their foot paths towards each other
    crossed = preset('tripod').replace(angle_offset=[1.5, -1.5, 0, 0, 0, 0])
    result = evaluate_gait(crossed, sim, collisions_fatal=True)
    assert not result.valid and 'self-collision' in result.reason
    assert 'link_1' in result.reason and 'link_2' in result.reason


def test_unreachable_gait_returns_the_failure_value(sim):
    result = evaluate_gait(preset('tripod').replace(radius=[0.3] * 6), sim)
    assert (
        not result.valid and result.fitness == 0.0 and result.reason.startswith('unreachable: leg')
    )


@pytest.mark.slow
@pytest.mark.parametrize('engine', ENGINES)
def test_friction_is_configurable(engine):
    # Without friction no horizontal force reaches the robot, so its base cannot travel; a little
    # friction already lets it walk (how much depends on how hard the stance feet fight each
    # other: stiff PyBullet servos slip at mu 0.05, compliant MuJoCo servos barely need it).
    with create_simulator(SimConfig(engine=engine, friction=0.0)) as ice:
        none = evaluate_gait(preset('tripod'), ice, collisions_fatal=False)
    with create_simulator(SimConfig(engine=engine)) as normal:
        fast = evaluate_gait(preset('tripod'), normal, collisions_fatal=False).speed
    assert none.valid and abs(none.speed) < 0.02 and fast > 0.25
    with pytest.raises(ValueError, match='friction'):
        SimConfig(friction=-1)


def _foot_floor_friction(sim) -> float:
    """Return the coefficient where foot 1 meets the floor, read by the engine's own rule."""
    if sim.config.engine == 'pybullet':  # Bullet multiplies the two surfaces'
        import pybullet as p

        foot = p.getDynamicsInfo(sim.body, sim._foot_links[0], physicsClientId=sim.client)[1]
        floor = p.getDynamicsInfo(sim.plane, -1, physicsClientId=sim.client)[1]
        return foot * floor
    if sim.config.engine == 'mujoco':  # MuJoCo takes the larger
        import mujoco

        floor = mujoco.mj_name2id(sim.m, mujoco.mjtObj.mjOBJ_GEOM, 'floor')
        tibia = mujoco.mj_name2id(sim.m, mujoco.mjtObj.mjOBJ_BODY, 'link_1_3')
        feet = [g for g in range(sim.m.ngeom) if sim.m.geom_bodyid[g] == tibia]
        return max(sim.m.geom_friction[floor, 0], *(sim.m.geom_friction[g, 0] for g in feet))
    # DART takes the smaller
    world = sim.world
    coefficients = []
    for name in ('link_1_3', sim._ground_name):
        body = next(
            world.getSkeleton(i).getBodyNode(name)
            for i in range(world.getNumSkeletons())
            if world.getSkeleton(i).getBodyNode(name) is not None
        )
        coefficients += [
            body.getShapeNode(k).getDynamicsAspect().getFrictionCoeff()
            for k in range(body.getNumShapeNodes())
            if body.getShapeNode(k).hasDynamicsAspect()
        ]
    return min(coefficients)


@pytest.mark.parametrize('engine', ENGINES)
@pytest.mark.parametrize('mu', [None, 0.49, 1.5])
def test_a_foot_meets_the_floor_at_the_configured_friction_on_every_engine(engine, mu):
    # one setting, one meaning: each engine combines two surfaces' coefficients its own way
    # (product, larger, smaller), and sets its surfaces so that the contact gets SimConfig's
    with create_simulator(SimConfig(engine=engine, friction=mu)) as sim:
        assert _foot_floor_friction(sim) == pytest.approx(1.0 if mu is None else mu, abs=1e-9)


def _standing_femur_error(config: SimConfig) -> float:
    """Return the femurs' mean |target - angle| after 1 s standing in the tripod's first pose."""
    with create_simulator(config) as sim:
        table = build_joint_table(preset('control'), rate=1.0 / sim.dt)
        rows = sim.prepare_rows(table.positions[:1], table.velocities[:1])
        sim.reset(table.positions[0])
        for _ in range(round(1.0 / sim.dt)):
            sim.apply_row(rows, 0)
            sim.step()
        error = sim.joint_states()[0] - np.clip(table.positions[0], sim.lower, sim.upper)
        return float(np.mean(np.abs(error[1::3])))


def test_pybullets_rx_servos_give_under_load_as_the_rx_model_does():
    # The femurs carry the body. The RX servo's compliance (the data sheet's slope, the model
    # MuJoCo and DART share, PyBullet's default) lets them give about 0.009 rad on MuJoCo;
    # Bullet's position motor, the thesis simulator's, holds them to 0.0004 (measured).
    mujoco = _standing_femur_error(SimConfig(engine='mujoco'))
    rx = _standing_femur_error(SimConfig(engine='pybullet'))
    position = PyBulletSettings(servo='position')
    thesis = _standing_femur_error(SimConfig(engine='pybullet', pybullet=position))
    assert mujoco / 3 < rx < 3 * mujoco, (rx, mujoco)
    assert thesis < mujoco / 10, (thesis, mujoco)
    with pytest.raises(ValueError, match='servo'):
        PyBulletSettings(servo='stepper')


def test_pybullets_rx_servos_do_not_fling_a_gait_whose_legs_collide():
    # This gait drives two tibias into each other from its first step. With Bullet's joint
    # speed clamp on, the rx servos flung the body 7.3 m in 5 s (measured): the clamp takes a
    # joint's speed away without a force. The rx servo's back-EMF is its speed limit instead;
    # the body now moves as on the other engines (MuJoCo 0.16 m, the position motor 0.11 m).
    gait = from_genotype(random_reachable_genotypes(5, seed=8)[1])
    with create_simulator(SimConfig(engine='pybullet')) as sim:
        result = evaluate_gait(gait, sim, collisions_fatal=False, record_tilt=True)
    assert result.collision_steps > 0
    assert abs(result.fitness) < 0.5, result.fitness


def test_a_numerical_blow_up_is_a_failed_evaluation_with_the_reason():
    stiff = MujocoSettings(back_emf=False, compliance_slope=1, integrator='euler', time_step=0.01)
    with create_simulator(SimConfig(engine='mujoco', mujoco=stiff)) as sim:
        result = evaluate_gait(preset('tripod'), sim, collisions_fatal=False)
    assert (
        not result.valid and result.fitness == 0.0 and 'physics became unstable' in result.reason
    )


@pytest.mark.slow
def test_a_batch_equals_one_gait_at_a_time(sim):
    genotypes = list(random_reachable_genotypes(4, seed=11)) + [preset('tripod'), preset('wave')]
    batch = evaluate_gaits(genotypes, sim, collisions_fatal=False)
    single = [evaluate_gait(g, sim, collisions_fatal=False) for g in reversed(genotypes)][::-1]
    assert [_fingerprint(r) for r in batch] == [_fingerprint(r) for r in single]


def test_unknown_engine_is_refused_with_the_known_ones():
    with pytest.raises(
        ValueError, match="unknown physics engine 'ode'; choose one of: pybullet, mujoco"
    ):
        SimConfig(engine='ode')


def test_motor_power_off_lets_the_robot_sag_and_on_holds_it_again():
    for engine in ENGINES:
        with create_simulator(SimConfig(engine=engine)) as sim:
            q0 = preset('tripod')
            from hexapod_gait import build_joint_table

            table = build_joint_table(q0, rate=1.0 / sim.dt)
            sim.reset(table.positions[0])
            rows = sim.prepare_rows(table.positions[:1], table.velocities[:1])
            for _ in range(120):
                sim.apply_row(rows, 0)
                sim.step()
            standing = sim.base_pose()[0][2]
            sim.set_motor_power(False)
            for _ in range(240):
                sim.apply_row(rows, 0)
                sim.step()
            assert sim.base_pose()[0][2] < standing - 0.02, engine  # no servo torque: it collapses
            sim.set_motor_power(True)


@pytest.mark.parametrize('duration', [0.0, -1.0, float('nan'), 1e-4])
def test_a_duration_without_a_single_step_is_refused(sim, duration):
    with pytest.raises(ValueError, match='duration'):
        evaluate_gait(preset('tripod'), sim, duration=duration)
