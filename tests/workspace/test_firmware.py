# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The C++ firmware module (firmware/) against the Python model it implements.

Generated constants, the STM32F407 cross build, and the differential tests (same bytes, states
and gait tables out).
"""

from __future__ import annotations

import os
from pathlib import Path
import re
import subprocess
import sys

from hexapod_bridge.emulator.differential import (
    compare,
    fuzz,
    replay_tool,
    run_model,
    run_native,
    TABLE_TOLERANCE,
    VELOCITY_LIMIT,
)
from hexapod_bridge.emulator.native import NativeFirmware
from hexapod_bridge.emulator.scripts import LINK_FAULTS, link_session_script, Script
from hexapod_bridge.protocol import extension as ext
from hexapod_bridge.protocol import legacy
from hexapod_gait import build_joint_table, preset, PRESETS, ROBOT_RATE
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
FIRMWARE = ROOT / 'firmware'


def test_generated_constants_are_up_to_date():
    result = subprocess.run(
        [sys.executable, str(FIRMWARE / 'tools' / 'gen_constants.py'), '--check'],
        capture_output=True,
        text=True,
    )
    assert result.returncode == 0, result.stderr


@pytest.mark.slow
def test_cross_build_for_the_stm32f407_fails_on_no_warning_and_fits(tmp_path):
    result = subprocess.run(
        ['make', '-C', str(FIRMWARE), 'arm', f'BUILD={tmp_path}'],
        capture_output=True,
        text=True,
    )
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    bench = dict(re.findall(r'^BENCH (\S+) (\d+) bytes$', result.stdout, re.M))
    print(
        '\n'.join(line for line in result.stdout.splitlines() if line.startswith(('BENCH', '#')))
    )
    objects = sorted(p.name for p in tmp_path.glob('*.o'))
    assert objects == ['crc16.o', 'firmware.o', 'gait.o', 'probe0.o', 'receiver.o']
    # the STM32F407: 1 MiB flash, 128 KiB SRAM (+64 KiB CCM); the module must leave room
    assert int(bench['firmware_flash_linked']) < 64 * 1024
    assert int(bench['firmware_ram_instance']) < 96 * 1024
    assert int(bench['firmware_ram_module_static']) == 0  # everything lives in the instance


def test_the_replay_tool_is_built_with_the_sanitizers():
    symbols = subprocess.run(['nm', replay_tool()], capture_output=True, text=True).stdout
    assert '__asan_init' in symbols and '__ubsan_handle' in symbols


@pytest.mark.parametrize('name', sorted(PRESETS))
def test_compiled_tables_match_hexapod_gait_joint_by_joint(name):
    """Each preset (and an omnidirectional, turning gait) uploaded: the module's table."""
    gait = preset(name)
    values = ext.gait_values(gait)
    fw = NativeFirmware(now_ms=0)
    for frame in ext.upload_frames(values, 3, 1):
        fw.receive(frame, 1)
    assert fw.state().gait_id == 3, fw.out_radio.hex()
    positions, velocities = fw.table()
    expected = build_joint_table(ext.gait_from_values(ext.quantise(values)), rate=ROBOT_RATE)
    assert positions.shape == expected.positions.shape == (120, 18)
    dp = np.abs(positions - expected.positions).max(axis=0)
    dv = np.abs(velocities - np.clip(expected.velocities, -VELOCITY_LIMIT, VELOCITY_LIMIT))
    print(f'{name}: max |position error| per joint {np.round(dp, 6).tolist()}')
    assert dp.max() <= TABLE_TOLERANCE['position']
    assert dv.max() <= TABLE_TOLERANCE['velocity']


def test_a_turning_crabbing_gait_matches_too():
    gait = preset('tripod').replace(crab_angle=2.0, turn_rate=0.4, body_velocity=0.1)
    fw = NativeFirmware()
    for frame in ext.upload_frames(ext.gait_values(gait), 9, 1):
        fw.receive(frame, 1)
    positions, _ = fw.table()
    expected = build_joint_table(ext.gait_from_values(ext.quantise(ext.gait_values(gait))))
    assert fw.state().gait_id == 9
    assert np.abs(positions - expected.positions[::2]).max() <= TABLE_TOLERANCE['position']


@pytest.mark.parametrize('fault', LINK_FAULTS)
def test_a_bridge_session_gives_the_same_bytes_states_and_tables(fault):
    script = link_session_script(fault, seed=1)
    model = run_model(script)
    result = compare(model, run_native(script))
    assert result.divergence is None, result.divergence
    assert result.events == sum(e[0] != 'T' for e in script.events)
    assert result.tables >= 1  # at least one upload got through and its tables were compared


def test_dead_servos_are_reported_by_both_between_walks():
    script = Script(dead_servos=frozenset({3, 14}))
    script.poll(0)  # start-up: the first tick checks the servos
    start = ext.encode_command(ext.Cmd.START_TRIAL, 1, ext.start_payload(0.2, 0))
    script.receive(10, start)
    for ms in range(20, 400, 20):
        script.poll(ms)
    model, native = run_model(script), run_native(script)
    assert compare(model, native).divergence is None
    sent = b''.join(
        bytes.fromhex(line.split()[1])
        for line in model
        if line.startswith('E ') and line.split()[1] != '-'  # '-': nothing sent
    )
    failed = legacy.encode_error(0x0B, 3) + legacy.encode_error(0x0B, 14)
    assert sent.count(failed) == 2  # at start-up and after the walk, never while walking


def test_the_module_folds_a_leg_with_a_dead_servo_as_the_model_does():
    from hexapod_sim.damage import FAILURE_POSE

    # servo 6 is leg 2's femur: its live coxa and tibia fold the leg (hexapod_sim.damage)
    script = Script(dead_servos=frozenset({6}))
    script.servos()  # before the first health check: the tripod's first pose
    script.poll(0)  # start-up: the health check finds servo 6 and folds leg 2 at once
    script.servos()
    start = ext.encode_command(ext.Cmd.START_TRIAL, 1, ext.start_payload(0.5, 0))
    script.receive(10, start)
    for ms in range(20, 900, 37):
        script.poll(ms)
        script.servos()
    model, native = run_model(script), run_native(script)
    result = compare(model, native)
    assert result.divergence is None, result.divergence
    targets = [np.array(line.split()[2:], float) for line in model if line.startswith('S ')]
    assert not np.allclose(targets[0][3:6], FAILURE_POSE)  # not folded before the check
    folded = targets[1:]
    assert all(np.allclose(t[3:6], FAILURE_POSE, atol=1e-6) for t in folded)
    assert np.ptp([t[0] for t in folded]) > 0.1  # leg 1 walks meanwhile
    assert int(model[-1].split()[1]) > 10  # the walk's rows were written


def test_the_comparison_finds_a_changed_byte_and_a_table_off_by_a_unit():
    script = link_session_script('clean')
    model = run_model(script)
    native = run_native(script)
    assert compare(model, native).divergence is None
    first_event = next(
        i for i, line in enumerate(native) if line.startswith('E ') and line.split()[1] != '-'
    )
    changed = list(native)
    changed[first_event] = changed[first_event].replace(' ', ' ff', 1)
    assert compare(model, changed).divergence.line == first_event
    table = next(i for i, line in enumerate(native) if line.startswith('T ')) + 1
    row = native[table].split()
    row[4] = repr(float(row[4]) + 2.5e-4)
    shifted = list(native)
    shifted[table] = ' '.join(row)
    assert compare(model, shifted).divergence.line == table


@pytest.mark.slow
def test_seeded_fuzz_of_100000_frames_finds_no_crash_and_no_divergence():
    result = fuzz(seed=2026, frames=100_000, dead_servos=frozenset({7}))
    print(result)
    assert result.divergence is None, result.divergence
    # the fuzz reached the paths that matter, not only rejections
    assert result.commits_ok >= 100 and result.trials >= 100 and result.tables >= 50


def test_the_emulator_refuses_dead_servos_on_three_legs(capsys):
    from hexapod_bridge.emulator.robot_emulator_cli import main

    with pytest.raises(SystemExit) as exit_info:
        main(['--dead-servo', '2', '--dead-servo', '5', '--dead-servo', '8'])
    assert exit_info.value.code == 2
    assert 'servos on 3 legs: at most 2 legs can fail' in capsys.readouterr().err


def test_without_the_host_build_the_native_emulator_says_what_to_build(tmp_path):
    env = dict(os.environ)
    env['AMENT_PREFIX_PATH'] = ':'.join(
        p for p in env.get('AMENT_PREFIX_PATH', '').split(':') if 'hexapod_firmware' not in p
    )
    result = subprocess.run(
        [
            sys.executable,
            '-m',
            'hexapod_bridge.emulator.robot_emulator_cli',
            '--firmware',
            'native',
            '--radio-link',
            str(tmp_path / 'radio'),
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=60,
    )
    assert result.returncode == 1
    assert 'package hexapod_firmware is not built' in result.stderr
    assert 'Traceback' not in result.stderr


# -- a robot whose legs are numbered otherwise than the URDF's (bridge_node's leg_map) ----------
def _demo_gait():
    """The demo map's fastest gait: every leg's values differ, so a mix-up of legs shows."""
    from hexapod_adapt.mapping.archive import load_archive
    from hexapod_adapt.mapping.maps import shipped_map
    from hexapod_gait import from_genotype

    archive = load_archive(shipped_map('demo_map.npz'))
    elites = archive.elite_indices()
    return from_genotype(archive.genotypes[elites[int(np.argmax(archive.fitness[elites]))]])


def test_the_module_and_the_model_agree_on_a_robot_numbered_otherwise():
    # the mirrored numbering of the real robot's firmware, a dead femur (servo 6: robot leg 2,
    # URDF leg 6) and an asymmetric gait uploaded: bytes, states, tables and servo targets
    script = Script(dead_servos=frozenset({6}), leg_map=ext.MIRRORED_LEG_MAP)
    script.poll(0)
    script.table()  # the compiled-in tripod, in the robot's slots
    values = ext.gait_values(_demo_gait(), ext.MIRRORED_LEG_MAP)
    now = 10
    for frame in ext.upload_frames(values, 7, 1):
        script.receive(now, frame)
        now += 3
    script.table()
    script.receive(now, ext.encode_command(ext.Cmd.START_TRIAL, 2, ext.start_payload(0.5, 7)))
    for ms in range(now + 10, now + 800, 29):
        script.poll(ms)
        script.servos()
    model = run_model(script)
    result = compare(model, run_native(script))
    assert result.divergence is None, result.divergence
    assert result.tables == 2
    # the tables are the URDF robot's, each leg's joints in its slot
    first = model.index('T 120', model.index('T 120') + 1)
    rows = np.array([line.split() for line in model[first + 1 : first + 121]], float)
    urdf = build_joint_table(ext.gait_from_values(ext.quantise(ext.gait_values(_demo_gait()))))
    expected = ext.joints_in_slots(urdf.positions[::2], ext.MIRRORED_LEG_MAP)
    assert np.abs(rows[:, :18] - expected).max() <= TABLE_TOLERANCE['position']
    assert np.abs(rows[:, :18] - urdf.positions[::2]).max() > 0.1  # the slots differ from URDF's


def test_a_leg_map_that_is_no_permutation_is_refused_by_the_module():
    with pytest.raises(RuntimeError, match='hx_init refused the configuration'):
        run_native(Script(leg_map=(1, 1, 2, 3, 4, 5)))
    with pytest.raises(ext.ExtensionError, match='permutation'):
        NativeFirmware(leg_map=(1, 2, 3, 4, 5, 7))


@pytest.mark.parametrize('firmware', ['python', 'native'])
def test_a_robot_numbered_otherwise_walks_a_gait_as_the_urdf_robot_does(firmware):
    from hexapod_bridge.emulator.consecutive import ConsecutiveTrials
    from hexapod_sim import create_simulator, SimConfig

    gait = _demo_gait()

    def walk(leg_map, robot_leg_map=None):
        with create_simulator(SimConfig(engine='mujoco')) as sim:
            robot = ConsecutiveTrials(
                sim, 0, noise=None, leg_map=leg_map, firmware=firmware, robot_leg_map=robot_leg_map
            )
            return np.array(robot.measure(gait, 2.0).true_move)

    urdf = walk(ext.IDENTITY_LEG_MAP)
    assert urdf[0] > 0.2  # it walks
    for leg_map in (ext.MIRRORED_LEG_MAP, (3, 1, 2, 6, 4, 5)):
        np.testing.assert_allclose(walk(leg_map), urdf, atol=1e-9)
    # a bridge whose leg_map is not the robot's numbering walks another gait
    mixed_up = walk(ext.MIRRORED_LEG_MAP, robot_leg_map=ext.IDENTITY_LEG_MAP)
    assert np.abs(mixed_up - urdf).max() > 0.02


def test_the_emulator_refuses_a_leg_map_that_is_no_permutation(capsys):
    from hexapod_bridge.emulator.robot_emulator_cli import main

    with pytest.raises(SystemExit) as exit_info:
        main(['--leg-map', '1', '2', '3', '4', '5', '5'])
    assert exit_info.value.code == 2
    assert '--leg-map: leg map must be a permutation of 1..6' in capsys.readouterr().err


def _tibia_rise(sim, play_for: float, step) -> tuple[np.ndarray, np.ndarray]:
    """Run ``step`` for ``play_for`` s; return each tibia's height range and the body's move."""
    start = sim.base_pose()[0].copy()
    heights = []
    t = 0.0
    while t < play_for:
        t += step()
        poses = sim.link_poses()
        heights.append([poses[f'link_{leg}_3'][0][2] for leg in range(1, 7)])
    return np.ptp(np.array(heights), axis=0), sim.base_pose()[0] - start


@pytest.mark.parametrize('engine', ['mujoco', 'pybullet'])
def test_the_leg_check_gait_lifts_only_its_leg_and_the_body_stays(engine):
    from hexapod_gait import build_joint_table
    from hexapod_gait.presets import leg_check
    from hexapod_sim import create_simulator, SimConfig

    with create_simulator(SimConfig(engine=engine)) as sim:
        table = build_joint_table(leg_check(3), rate=1.0 / sim.dt)
        sim.reset(table.positions[0])
        rows = sim.prepare_rows(table.positions, table.velocities)
        row = iter(range(10**6))

        def step():
            sim.apply_row(rows, next(row) % len(table))
            sim.step()
            return sim.dt

        rise, moved = _tibia_rise(sim, 2.0, step)
    print(engine, np.round(rise, 4), np.round(moved, 4))
    assert rise[2] > 0.05 and np.delete(rise, 2).max() < 0.005
    assert np.abs(moved).max() < 0.005
    with pytest.raises(ValueError, match='leg must be 1..6'):
        leg_check(7)


def test_leg_check_lifts_the_urdf_leg_on_a_robot_numbered_otherwise():
    from hexapod_bridge.emulator.consecutive import ConsecutiveTrials
    from hexapod_gait.presets import leg_check
    from hexapod_sim import create_simulator, SimConfig

    with create_simulator(SimConfig(engine='mujoco')) as sim:
        robot = ConsecutiveTrials(
            sim, 0, noise=None, leg_map=ext.MIRRORED_LEG_MAP, firmware='native'
        )
        upload = robot.link.upload(leg_check(2))
        while not upload.done:
            robot.step()
        assert upload.ok, upload.message
        robot.link.start_trial(2.0, upload.result['gait_id'])

        def step():
            robot.step()
            return 0.002

        rise, _ = _tibia_rise(sim, 0.5, step)  # standing to the gait's first pose, then walking
        rise, moved = _tibia_rise(sim, 2.0, step)
    print(np.round(rise, 4), np.round(moved, 4))
    assert rise[1] > 0.05 and np.delete(rise, 1).max() < 0.005  # URDF leg 2 (robot leg 6)
    assert np.abs(moved).max() < 0.005
