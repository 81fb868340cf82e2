# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The MuJoCo engine's own choices: settings ranges, servo model, blow-up detection."""

from __future__ import annotations

from hexapod_gait import preset
from hexapod_sim import create_simulator, evaluate_gait, evaluate_gaits, SimConfig
from hexapod_sim.engine_settings import MujocoSettings
import numpy as np
import pytest


@pytest.mark.parametrize(
    'field,value,match',
    [
        ('compliance_slope', 0.0, r'compliance_slope must be in \[1, 256\]'),
        ('time_step', 0.5, r'time_step must be in'),
        ('contact_timeconst', 0.001, r'contact_timeconst must be in'),  # < 2 time steps: unstable
        ('iterations', 0, r'iterations must be in \[1, 1000\]'),
        ('iterations', 2.5, r'iterations must be an integer'),
        ('armature', float('nan'), r'armature must be in'),
        ('cone', 'round', r'cone must be one of pyramidal, elliptic'),
        ('integrator', 'rk9', r'integrator must be one of'),
        ('substeps', 0, r'substeps must be in \[1, 64\]'),
        ('substeps', 2.0, r'substeps must be an integer'),
    ],
)
def test_mujoco_settings_out_of_range_are_refused(field, value, match):
    with pytest.raises(ValueError, match=match):
        MujocoSettings(**{field: value})


def test_mujoco_servos_respect_the_urdf_effort_limits():
    with create_simulator(SimConfig(engine='mujoco')) as sim:
        result = evaluate_gait(preset('tripod'), sim, collisions_fatal=False)
        efforts = np.array([lim.effort for lim in sim.model.limits])
        _, _, torque = sim.joint_states()
        assert result.valid and np.all(np.abs(torque) <= efforts + 1e-9)
        # the servo gain follows from the stall torque and the compliance slope (32 x 0.29 deg)
        assert sim.settings.servo_kp(3.464) == pytest.approx(3.464 / (32 * np.radians(300 / 1024)))


#: A demo-map gait that blows up MuJoCo when the servos have no back-EMF damping (from a sweep).
BLOWS_UP_WITHOUT_BACK_EMF = [
    0.411886736030811,
    0.014057925788723155,
    0.788538185685143,
    0.42221799967350887,
    0.7504814782561686,
    0.05494747988027441,
    0.988851117596404,
    0.6918646326468704,
    0.3921038615837734,
    0.10614140681501028,
    0.4466289770636665,
    0.9648471310128469,
    0.2128056869356695,
    0.33351348221912314,
    0.32741824778381523,
    1.0,
    1.0,
    0.7830856788941308,
    0.41782029280566696,
    0.10673254783136216,
    0.0,
    0.982857411531142,
    0.8269588476197195,
    0.7634901616330082,
    0.18557554116538633,
    0.7397557562481006,
    0.513996287413884,
    0.890498664296602,
    0.6862991581832442,
    0.027866336417504918,
    0.012786569430227029,
    0.10752555490201114,
]


#: Demo-map gaits 405, 163 and 485 (the shipped demo_map.npz), which blew up without back-EMF on
#: a second machine (AMD EPYC, 2026-11-25), where the gait above ended on its back instead: when a
#: blow-up happens is chaotic, and it moves with the processor's floating point. The tests take
#: the first gait that blows up here.
BLOW_UP_CANDIDATES = (
    BLOWS_UP_WITHOUT_BACK_EMF,
    [
        0.45175463949466116,
        0.011788917402369085,
        0.8824755968243185,
        0.3833206652552253,
        0.7249275008382469,
        0.0,
        1.0,
        0.7229244089347999,
        0.48864085176207095,
        0.0,
        0.322060546612167,
        1.0,
        0.23015843922769716,
        0.42118795287988847,
        0.379079303076399,
        1.0,
        1.0,
        0.7374175878067509,
        0.248157085439467,
        0.01863351007537613,
        0.0025964309287196154,
        1.0,
        0.7906494225777487,
        0.7948976078055202,
        0.2382456421430287,
        0.7785727922459017,
        0.6703553423732073,
        0.9626237494646517,
        0.7073574297364609,
        0.0028835451050420423,
        0.0,
        0.08447092555780542,
    ],
    [
        0.4664176507433134,
        0.07807244828782686,
        0.7437225483608034,
        0.4128371012681526,
        0.6874254192223979,
        0.04065738519841852,
        0.9610619301299855,
        0.6670182912051238,
        0.4300816970770508,
        0.15985041715892156,
        0.4720595423569169,
        0.9649544248524788,
        0.22612630919284898,
        0.32570670964670784,
        0.3663843013250482,
        0.9517146844127113,
        0.9978705824170633,
        0.7561276164979693,
        0.4626592872235492,
        0.08477578599687963,
        0.029119392093347816,
        0.9737614981813427,
        0.7862964010399269,
        0.7371719868974225,
        0.17997351624856142,
        0.6952113146514826,
        0.489897674482522,
        0.9007864698394404,
        0.6331688691194698,
        0.0363290582648839,
        0.04468066757233859,
        0.16114943804870444,
    ],
    [
        0.45877208603363157,
        0.0,
        0.8522483854188082,
        0.4052290115714701,
        0.7481683267051484,
        0.026424479335749197,
        1.0,
        0.7227517942178749,
        0.4798019717223292,
        0.003830346335966045,
        0.4205882905052225,
        1.0,
        0.20860017264493103,
        0.37990245568762954,
        0.35114865547480645,
        1.0,
        1.0,
        0.7499469053259559,
        0.31051050002358765,
        0.04073637617911072,
        0.014914924653248722,
        1.0,
        0.7798442300530766,
        0.798429064753292,
        0.20127940805447952,
        0.7638204211538105,
        0.6066393082249185,
        0.9667556522112227,
        0.6976859196383763,
        0.0,
        0.0,
        0.06704721676475688,
    ],
)
UNSTABLE = 'the MuJoCo physics became unstable at t = '


def _blows_up_here(sim) -> tuple[list, str]:
    """Return (the first candidate gait that blows up on this machine, its reason)."""
    for gait in BLOW_UP_CANDIDATES:
        result = evaluate_gait(gait, sim, collisions_fatal=False)
        if result.reason.startswith(UNSTABLE):
            return gait, result.reason
    raise AssertionError('none of the candidate gaits blows up MuJoCo without back-EMF here')


def _seconds(reason: str) -> float:
    """Return the time a reason names ('... at t = 1.234 s ...')."""
    return float(reason.split(' at t = ')[1].split(' s')[0])


def test_a_blow_up_inside_a_batch_fails_only_that_gait():
    """Check each rollout's own time line: MuJoCo resets itself after a blow-up, carrying on."""
    with create_simulator(
        SimConfig(engine='mujoco', mujoco=MujocoSettings(back_emf=False))
    ) as sim:
        gait, alone = _blows_up_here(sim)
        batch = evaluate_gaits(
            [gait, preset('tripod'), preset('wave')],
            sim,
            collisions_fatal=False,
        )
    assert [r.valid for r in batch] == [False, True, True]
    assert batch[0].reason == alone


def test_with_collisions_fatal_a_rollout_reports_what_happened_first():
    """A collision before a blow-up ends the gait first (a whole rollout would blow up later)."""
    stiff = MujocoSettings(back_emf=False, compliance_slope=1, integrator='euler', time_step=0.01)
    with create_simulator(SimConfig(engine='mujoco', mujoco=stiff)) as sim:
        whole = evaluate_gait(preset('tripod'), sim, collisions_fatal=False)
        first = evaluate_gaits([preset('tripod')], sim, collisions_fatal=True)[0]
    # (0.200 s on one machine, 0.210 s on another: the moment of a blow-up is chaotic)
    assert whole.reason.startswith(UNSTABLE) and 0.1 < _seconds(whole.reason) < 0.5
    assert first.reason == 'self-collision link_3_1 / link_3_3 at t = 0.040 s'
    with create_simulator(
        SimConfig(engine='mujoco', mujoco=MujocoSettings(back_emf=False))
    ) as sim:
        gait, blow_up = _blows_up_here(sim)
        first = evaluate_gaits([gait], sim, collisions_fatal=True)[0]
    assert first.reason.startswith('self-collision ')
    assert _seconds(first.reason) < _seconds(blow_up)


def _gaits_that_collide_or_not() -> list:
    low = preset('tripod').replace(body_height=0.04, body_velocity=0.1, step_height=[0.02] * 6)
    crossed = preset('tripod').replace(angle_offset=[1.5, -1.5, 0, 0, 0, 0])
    return [preset('tripod'), low, preset('wave'), crossed, preset('quadruped')]


def test_a_rollout_that_stops_at_its_first_collision_is_the_whole_rollout_cut_short(
    monkeypatch,
):
    """
    Collisions fatal: each gait is played in chunks up to its first collision.

    The chunks carry the state and the solver's warm start, so every result is bit for bit the
    whole rollout's (its first collision, feet, pose), and a gait that collides early costs
    only the steps up to the end of that chunk.
    """
    from hexapod_gait import build_joint_table
    from hexapod_sim.physics import mujoco_engine
    from hexapod_sim.simulator import JointRows

    played: list[int] = []
    real = mujoco_engine.mj_rollout.rollout

    def counting(*args, **kwargs):
        played.append(int(np.shape(args[3])[1]))  # the control's steps
        return real(*args, **kwargs)

    with create_simulator(SimConfig(engine='mujoco')) as sim:
        tables = []
        for gait in _gaits_that_collide_or_not():
            t = build_joint_table(gait, rate=1.0 / sim.dt)
            tables.append(JointRows(t.positions, t.velocities))
        n = 1200
        whole = sim.rollout(tables, n, stop_on_collision=False)
        monkeypatch.setattr(mujoco_engine.mj_rollout, 'rollout', counting)
        cut = sim.rollout(tables, n, stop_on_collision=True)
    collides = [w.first_collision is not None for w in whole]
    assert collides == [False, True, False, True, False]
    for w, c, hit in zip(whole, cut, collides):
        assert c.first_collision == w.first_collision
        if hit:  # the collision's step, as the per-step loop counts it
            assert c.steps < n and c.collision_steps == 1
        else:
            assert c.steps == w.steps == n and c.collision_steps == 0
            np.testing.assert_array_equal(c.final_position, w.final_position)
            np.testing.assert_array_equal(c.final_orientation, w.final_orientation)
            np.testing.assert_array_equal(c.contact_steps, w.contact_steps)
    # the colliding gaits stopped within a chunk of their collision: far fewer steps played
    assert sum(played) < 3 * n + 2 * mujoco_engine.COLLISION_CHUNKS[1] + n // 2


def test_with_substeps_the_native_batch_is_the_per_step_loop():
    """
    Four physics steps per 240 Hz row: the C rollout and the per-step loop play the same steps.

    Bit for bit: the row's target held through its physics steps, a contact in any of them
    counted, the first collision found at the physics step it happened.
    """
    from hexapod_gait import build_joint_table
    from hexapod_sim.simulator import JointRows, Simulator

    config = SimConfig(engine='mujoco', mujoco=MujocoSettings(substeps=4))
    with create_simulator(config) as sim:
        assert sim.m.opt.timestep == pytest.approx(sim.dt / 4)
        tables = []
        for gait in _gaits_that_collide_or_not():
            t = build_joint_table(gait, rate=1.0 / sim.dt)
            tables.append(JointRows(t.positions, t.velocities))
        n = 480
        native = sim.rollout(tables, n, stop_on_collision=False, record_contacts=True)
        for table, fast in zip(tables, native):
            slow = Simulator._play(sim, table, n, stop_on_collision=False, record_contacts=True)
            assert fast.first_collision == slow.first_collision
            assert fast.collision_steps == slow.collision_steps
            np.testing.assert_array_equal(fast.contact_steps, slow.contact_steps)
            np.testing.assert_array_equal(fast.final_position, slow.final_position)
    assert [r.first_collision is not None for r in native] == [False, True, False, True, False]


def test_one_step_per_row_keeps_the_fingerprint_it_had_before_substeps_existed():
    """The maps, ceilings and banks made at one step per row stay valid; 4 is another model."""
    plain = SimConfig(engine='mujoco').fingerprint()
    assert 'substeps' not in plain['settings']
    # the shipped maps' hash (made before substeps existed)
    assert plain['settings_sha256'] == (
        'e6009aaf0b5e44fc4116c6124b44deaa7de0719557b100c5bbed7c3e8256ccd4'
    )
    four = SimConfig(engine='mujoco', mujoco=MujocoSettings(substeps=4)).fingerprint()
    assert four['settings']['substeps'] == 4
    assert four['settings_sha256'] != plain['settings_sha256']


#: The fastest gait of the CMA-MAE default map (niche 13176, 0.617 m/s on MuJoCo at one step
#: per row): a gait that loads the servos hard.
FAST_GENOTYPE = [
    0.9140497994578927, 0.9813589166515588, 0.34681093127766743, 0.9336867061456019,
    0.7100286208535209, 0.6414829151810766, 0.6253300265414615, 0.7066108819505961,
    0.9732674477398345, 0.450215796919652, 0.3455223816466764, 0.06365990548875962,
    0.5580459622040497, 0.8190060280582581, 0.7648814399712117, 0.4320627989820767,
    0.25352164347404166, 0.45715639667366154, 0.6556969986519405, 0.8913314208628762,
    0.7753192899363357, 0.3729660662507439, 0.5191244044981446, 0.5900625751737243,
    0.5758338811889603, 0.18206625544383215, 0.350953166758257, 0.4562613792390796,
    0.6194730125650844, 0.7797757439002033, 0.3503008218245981, 0.2695879834936182,
]  # fmt: skip


def test_a_map_is_judged_on_each_engine_at_its_converged_step():
    """SimConfig.converged: the engine's default settings but for its substeps."""
    from dataclasses import replace

    from hexapod_sim.simulator import CONVERGED_SUBSTEPS

    for engine, substeps in CONVERGED_SUBSTEPS.items():
        config = SimConfig.converged(engine)
        assert config.engine == engine and config.engine_settings().substeps == substeps
        default = SimConfig(engine=engine).engine_settings()
        assert config.engine_settings() == replace(default, substeps=substeps)
    with pytest.raises(ValueError, match='unknown physics engine'):
        SimConfig.converged('ode')


def test_substeps_change_a_fast_gait_and_not_the_tripod():
    """
    The tripod walks alike at 1 and 4 physics steps per row; a gait that loads the servos hard.

    Does not (studies/engines, "Where the engines differ", item 6): one step per row has not
    converged on it.
    """
    from hexapod_gait import from_genotype

    gait = from_genotype(np.array(FAST_GENOTYPE))
    speeds = {}
    for n in (1, 4, 8):
        with create_simulator(
            SimConfig(engine='mujoco', mujoco=MujocoSettings(substeps=n))
        ) as sim:
            speeds[n] = [r.speed for r in evaluate_gaits([preset('tripod'), gait], sim)]
    tripod = [speeds[n][0] for n in (1, 4, 8)]
    assert max(tripod) - min(tripod) < 0.02, tripod
    # measured: the tripod 0.303, 0.290, 0.288 m/s; the gait 0.617, 0.261, 0.233 (16: 0.232)
    assert abs(speeds[4][1] - speeds[8][1]) < 0.05, speeds
    assert speeds[1][1] - speeds[8][1] > 0.2, speeds


def test_mujoco_model_takes_limits_from_the_urdf():
    """The compiled model's joint ranges and servo force limits are the URDF's (tables 3.8-9)."""
    with create_simulator(SimConfig(engine='mujoco')) as sim:
        for lim in sim.model.limits:
            np.testing.assert_allclose(
                sim.m.joint(lim.name).range, (lim.lower, lim.upper), err_msg=lim.name
            )
            np.testing.assert_allclose(
                sim.m.actuator(lim.name).forcerange, (-lim.effort, lim.effort), err_msg=lim.name
            )
            # back-EMF: the URDF velocity limit is the no-load speed
            assert sim.m.dof_damping[sim.m.joint(lim.name).dofadr[0]] == pytest.approx(
                lim.effort / lim.velocity
            )


def test_mujoco_renders_the_robot():
    """A frame from MuJoCo's renderer (OSMesa headless, set up by the bootstrap and env.sh)."""
    with create_simulator(SimConfig(engine='mujoco')) as sim:
        sim.reset(np.zeros(len(sim.model.joint_names)))
        frame = sim.render(160, 120)
    assert frame.shape == (120, 160, 3) and frame.dtype == np.uint8
    assert frame.std() > 10  # not a blank image: robot, floor and shadow differ


def test_the_per_step_path_reports_a_blow_up_too():
    """sim_node and the emulator step one at a time: the step that blew up says so."""
    stiff = MujocoSettings(back_emf=False, compliance_slope=1, integrator='euler', time_step=0.01)
    with create_simulator(SimConfig(engine='mujoco', mujoco=stiff)) as sim:
        from hexapod_gait import build_joint_table

        table = build_joint_table(preset('tripod'), rate=1.0 / sim.dt)
        rows = sim.prepare_rows(table.positions, table.velocities)
        sim.reset(table.positions[0])
        flagged = []
        for k in range(500):
            sim.apply_row(rows, k % len(table.positions))
            flagged.append(sim.step().unstable)
    assert any(flagged) and not flagged[0]


def test_a_damage_leaves_nothing_behind_when_another_replaces_it():
    """The broad phase's body masks follow the geoms' (a lifted leg's outlived it: CI found it)."""
    from hexapod_sim.damage import Damage
    from hexapod_sim.sampling import random_feasible_genotypes

    used = create_simulator(SimConfig(engine='mujoco'))
    fresh = create_simulator(SimConfig(engine='mujoco'))
    genes = list(random_feasible_genotypes(3, seed=3, sim=fresh)[0])
    for before in (Damage.of('unpowered_femur', [2]), Damage.lifted([1])):
        evaluate_gaits(genes, used, collisions_fatal=False, failed_legs=before)
    damage = Damage.lifted([2])
    after = [
        r.speed for r in evaluate_gaits(genes, used, collisions_fatal=False, failed_legs=damage)
    ]
    new = [
        r.speed for r in evaluate_gaits(genes, fresh, collisions_fatal=False, failed_legs=damage)
    ]
    assert after == new
    np.testing.assert_array_equal(used.m.body_contype, fresh.m.body_contype)
    np.testing.assert_array_equal(used.m.body_conaffinity, fresh.m.body_conaffinity)


@pytest.mark.parametrize('substeps', [1, 4])
def test_a_link_on_the_floor_is_found_and_named_alike_by_step_and_rollout(substeps):
    """
    One sensor counts the robot's floor contacts: more than its feet's means a link is down.

    A gait too low for its body (0.04 m) puts a link on the floor; the per-step loop and the
    batch rollout find it in the same row and name the same link, the first in the base, coxae,
    femurs order of those ``d.contact`` holds.
    """
    from hexapod_gait import build_joint_table
    from hexapod_sim.simulator import JointRows

    low = _gaits_that_collide_or_not()[1]
    config = SimConfig(engine='mujoco', mujoco=MujocoSettings(substeps=substeps))
    with create_simulator(config) as sim:
        t = build_joint_table(low, rate=1.0 / sim.dt)
        played = sim.rollout([JointRows(t.positions, t.velocities)], 240)[0]
        rows = sim.prepare_rows(t.positions, t.velocities)
        sim.reset(t.positions[0])
        first = None
        for k in range(240):
            sim.apply_row(rows, k % len(rows))
            report = sim.step()
            if report.collision is not None:
                first = (k, report.collision)
                break
    assert first is not None and first[1].endswith('touched the ground'), first
    link = first[1].split()[0]
    assert link == 'base_link' or link.startswith('link_') and link[-1] in '12'
    assert played.first_collision == f'{first[1]} at t = {(first[0] + 1) * sim.dt:.3f} s'
