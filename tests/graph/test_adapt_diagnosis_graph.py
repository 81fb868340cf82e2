# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A blind run through the graph names a damage nobody told adapt_node, says so, and stops itself.

sim_node holds the damage (set at start-up, as ``SetLegFailure`` sets it); the goal is blind, so
adapt_node does not ask the simulator. The diagnosis after each trial is on the goal's feedback,
on ``adapt/diagnosis`` and in the run's recording.
"""

from __future__ import annotations

from hexapod_msgs.action import Adapt
from hexapod_msgs.msg import DamageDiagnosis
from hexapod_sim.damage import Damage
from hexapod_util.recording import read_messages
from hexapod_util.ros_glue import EVENTS
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
    diagnosis after each is on the feedback. The bank holds lifted legs, not dead servos: the
    hypothesis it leads with is the dead servo's leg lifted (a folded leg carries nothing, as a
    lifted one), which the run goes on as (measured: named after the first trial, 2 trials).
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
        assert top == f'leg {leg} lifted' and said[-1].named == top, (leg, said[-1])
    finally:
        robot.stop()
