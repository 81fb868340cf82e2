# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A blind run through the graph names a damage nobody told adapt_node, says so, and stops itself.

sim_node holds the damage (set at start-up, as ``SetLegFailure`` sets it); the goal is blind, so
adapt_node does not ask the simulator. The diagnosis after each trial is on the goal's feedback,
on ``adapt/diagnosis`` and in the run's recording.
"""

from __future__ import annotations

import subprocess

from hexapod_msgs.action import Adapt
from hexapod_msgs.msg import DamageDiagnosis
from hexapod_sim.damage import Damage
from hexapod_util.recording import read_messages
from hexapod_util.ros_glue import EVENTS
import numpy as np
import pytest

from conftest import fast_sim_graph, NodeProcess, wait_for

pytestmark = [pytest.mark.ros, pytest.mark.slow]


def test_a_blind_run_names_the_hidden_damage_says_so_and_stops_by_itself(ros, launch, tmp_path):
    hidden = Damage.lifted([1, 4])
    fast_sim_graph(launch, [1, 4], record_dir=str(tmp_path / 'runs'))  # the default map
    published = ros.collect(DamageDiagnosis, 'adapt/diagnosis', EVENTS)
    run = ros.send_adapt(Adapt.Goal(blind=True), timeout=60)
    wait_for(run.done, 900, 'the blind run to end')
    result = run.result()
    assert result.success, result.message
    assert 'the damage is named from the trials among 21 hypotheses' in result.prior
    assert 1 <= result.trials < 24, result.message  # it stopped by itself, not on the budget
    said = [f.diagnosis for f in run.trials]
    assert len(said) == result.trials and all(d.hypotheses for d in said)
    assert said[-1].named == hidden.label, said[-1]
    assert said[-1].hypotheses[0] == hidden.label and said[-1].probabilities[0] >= 0.9
    assert not any(d.rescoring for d in said)  # legs 1+4 lifted is cached: no pause
    wait_for(lambda: len(published) == result.trials, 10, 'a diagnosis on adapt/diagnosis a trial')
    assert [d.named for d in published] == [d.named for d in said]
    recorded = [
        m for topic, m, _ in read_messages(result.mcap_path) if topic == '/adapt/diagnosis'
    ]
    assert [d.named for d in recorded] == [d.named for d in said]


def test_on_the_robot_path_a_blind_run_diagnoses_from_the_imu_and_the_trial_odometry(
    ros, launch, domain_id, tmp_path
):
    """
    The emulated robot (PyBullet) with a dead femur servo; the run is told nothing (blind).

    Each trial's record is the bridge's IMU attitude and the trial's mean velocity; the
    diagnosis after each is on the feedback. The first bank holds lifted legs, not dead servos:
    the hypothesis it leads with is the dead servo's leg lifted (a folded leg carries nothing,
    as a lifted one), which the run goes on as (measured: named after the first trial, 2
    trials); or, when that fits its trials badly, the wider bank's kinds on that leg (measured
    once: "leg 2 lifted, no_tibia, unpowered coxa or unpowered tibia" after trial 2). Either way
    the run names the dead servo's leg.
    """
    from hexapod_bridge.protocol.extension import IDENTITY_LEG_MAP
    from hexapod_bridge.reports import servo_report
    from std_srvs.srv import SetBool

    servo = 5
    leg = servo_report(servo, IDENTITY_LEG_MAP).leg
    radio, imu = str(tmp_path / 'radio'), str(tmp_path / 'imu')
    args = ['--radio-link', radio, '--imu-link', imu, '--sim', '--dead-servo', str(servo)]
    robot = NodeProcess('hexapod_bridge', 'robot_emulator', domain_id, tmp_path, args=args)
    try:
        wait_for(lambda: 'IMU /dev/pts' in robot.log(), 60, 'the emulator ports')
        launch('hexapod_bridge', 'bridge_node', params={'port': radio, 'imu_port': imu})
        launch('hexapod_adapt', 'adapt_node', params={'mode': 'robot', 'record_dir': ''})
        assert ros.call(SetBool, 'bridge_node/arm', SetBool.Request(data=True)).success
        run = ros.send_adapt(Adapt.Goal(blind=True, max_trials=4), timeout=60)
        wait_for(run.done, 900, 'the blind robot run to end')
        result = run.result()
        assert result.trials >= 1, result.message
        assert 'the damage is named from the trials among 21 hypotheses' in result.prior
        said = [f.diagnosis for f in run.trials]
        assert len(said) == result.trials and all(d.hypotheses for d in said), said
        top = said[-1].hypotheses[0]
        print('diagnosis after each trial:', [(d.hypotheses[0], d.named) for d in said])
        on_its_leg = f'leg {leg} '  # 'leg 2 lifted', 'leg 2 lifted, no_tibia or ...'
        assert top.startswith(on_its_leg) and said[-1].named.startswith(on_its_leg), said[-1]
    finally:
        robot.stop()


def test_a_short_intact_run_calibrates_the_gap_and_later_blind_runs_carry_it(
    ros, launch, tmp_path
):
    """
    adapt_node/calibrate: the last run's trials, walked intact, against the map's engine.

    The trials walk on PyBullet (sim_node's default engine), the hypotheses on MuJoCo (the
    default map's): the file holds that gap. A damaged file is refused and the last good kept.
    """
    from hexapod_adapt.mapping.archive import load_archive
    from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
    from hexapod_adapt.online.calibration import gap_key, load_gap
    from rcl_interfaces.msg import ParameterType, ParameterValue

    from conftest import executable, set_adapt_parameter

    gap = tmp_path / 'gap.npz'
    launch('hexapod_sim', 'sim_node', params={'real_time_factor': 0.0})
    launch('hexapod_gait', 'gait_node', params={'initial_preset': ''})
    node = launch(
        'hexapod_adapt', 'adapt_node', params={'record_dir': '', 'gap_calibration': str(gap)}
    )

    def calibrate() -> subprocess.CompletedProcess:  # as an operator does, with the command
        return subprocess.run(
            [str(executable('hexapod_adapt', 'adapt_service')), 'calibrate'],
            capture_output=True, text=True, timeout=120, stdin=subprocess.DEVNULL,
        )  # fmt: skip

    refused = calibrate()
    assert refused.returncode == 1 and 'no run on this map yet' in refused.stderr, refused
    intact = ros.send_adapt(Adapt.Goal(max_trials=3, alpha=1.0), timeout=60)
    wait_for(intact.done, 300, 'the intact run')
    assert intact.result().trials == 3, intact.result().message
    made = calibrate()
    assert made.returncode == 0 and 'calibrated on 3 gaits' in made.stdout, made
    calibration, gaits = load_gap(gap, gap_key(load_archive(shipped_map(DEFAULT_MAP)), 'mujoco'))
    assert gaits == 3 and np.isfinite(calibration.offset).all()
    damaged = tmp_path / 'damaged.npz'
    damaged.write_bytes(b'PK\x03\x04 not a calibration')
    text = ParameterValue(type=ParameterType.PARAMETER_STRING, string_value=str(damaged))
    answer = set_adapt_parameter(ros, 'gap_calibration', text)
    assert not answer.successful and 'damaged.npz' in answer.reason, answer.reason
    blind = ros.send_adapt(Adapt.Goal(blind=True, max_trials=2), timeout=60)

    def told():
        return [n for _, n in blind.notes_after(0.0) if 'gap calibrated on 3 intact gaits' in n]

    wait_for(lambda: told() or blind.done(), 300, 'the blind run to say it is calibrated')
    assert told() and str(gap) in told()[0], blind.notes_after(0.0)
    blind.cancel()
    wait_for(blind.done, 300, 'the cancelled blind run to end')
    assert node.alive()
