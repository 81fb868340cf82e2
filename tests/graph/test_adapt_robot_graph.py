# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
adapt_node on the robot's side of the graph: bridge_node with the emulated robot, manual mode.

Trials measured by the bridge's IMU odometry (the Python firmware model and the C++ module), the
operator's tape measure, a second request refused, Ctrl-C mid-run, a gait the robot refuses,
servo reports that are not to be believed, a status publisher that is not the bridge.
"""

from __future__ import annotations

import os

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.mapping.simulation import simulation_fingerprint
from hexapod_adapt.ros.adapt_action import BUSY
from hexapod_msgs.action import Adapt
from hexapod_msgs.msg import AdaptationTrial
from hexapod_sim import create_simulator, evaluate_gait
from hexapod_util.recording import read_messages
import numpy as np
import pytest

from conftest import forgers_are_ignored_and_named, status_log_qos, wait_for, WS

pytestmark = pytest.mark.ros


def _preset_archive(tmp_path):
    from hexapod_gait import preset
    from hexapod_gait.parameters import to_genotype

    with create_simulator() as sim:
        genes = np.array([to_genotype(preset(name)) for name in ('tripod', 'wave', 'quadruped')])
        results = [evaluate_gait(g, sim) for g in genes]
    desc = np.array([r.descriptor for r in results])
    return Archive(
        desc,
        np.array([r.fitness for r in results]),
        desc,
        genes,
        {'seed': 0, 'evaluations': 3, **simulation_fingerprint('pybullet')},
    ).save(tmp_path / 'presets.npz')


def _emulated_robot(launch, tmp_path, *extra):
    radio, imu = str(tmp_path / 'radio'), str(tmp_path / 'imu')
    emu = launch(
        'hexapod_bridge', 'robot_emulator', args=['--radio-link', radio, '--imu-link', imu, *extra]
    )
    wait_for(lambda: os.path.exists(radio) and os.path.exists(imu), 60, 'emulator ports')
    return emu, radio, imu


def _every_trial_measured_within_the_stated_accuracy(emu, trials, n: int) -> None:
    """Each of the run's ``n`` trials: walked to its end, its speed within the IMU's accuracy."""
    import json

    from hexapod_bridge.odometry import SPEED_ACCURACY

    wait_for(
        lambda: len(trials) == n and emu.log().count('TRIAL ') >= n, 20, 'every trial reported'
    )
    truths = [
        json.loads(line.split('TRIAL ', 1)[1])
        for line in emu.log().splitlines()
        if 'TRIAL ' in line
    ]
    for t, truth in zip(trials, truths):
        assert truth['state'] == 'done'
        assert abs(t.measured_speed - truth['speed']) <= SPEED_ACCURACY, (
            t.measured_speed,
            truth['speed'],
        )


@pytest.mark.slow
def test_adaptation_on_the_emulated_robot_uses_the_bridge_odometry(
    ros, launch, tmp_path, small_archive
):
    from std_srvs.srv import SetBool

    # the preset gaits: the IMU estimate's stated accuracy was measured on such calm gaits (a
    # random map gait can walk very differently on the emulated firmware; see docs/adaptation.md)
    path = _preset_archive(tmp_path)
    emu, radio, imu = _emulated_robot(launch, tmp_path, '--sim', '--imu-noise', '--seed', '3')
    bridge = launch('hexapod_bridge', 'bridge_node', params={'port': radio, 'imu_port': imu})
    node = launch(
        'hexapod_adapt',
        'adapt_node',
        params={'archive': str(path), 'mode': 'robot', 'record_dir': ''},
    )
    trials = ros.collect(AdaptationTrial, 'adapt/trials', 10)
    assert ros.call(SetBool, 'bridge_node/arm', SetBool.Request(data=True)).success
    response = ros.adapt(Adapt.Goal(max_trials=2, alpha=1.0), timeout=120)
    # one trial suffices when the measured speed beats every prediction (the tripod walks
    # ~0.288 m/s, as mapped)
    assert 1 <= response.trials <= 2, response.message
    _every_trial_measured_within_the_stated_accuracy(emu, trials, response.trials)
    assert node.alive() and bridge.alive() and emu.alive()


@pytest.mark.slow
def test_two_failed_legs_adapted_on_the_robot_running_the_cpp_firmware(ros, launch, tmp_path):
    """
    The whole robot path with the C++ firmware module: robot_emulator --firmware native.

    Two servos dead (legs 1 and 4 hang in the failure pose), adapt_node in robot mode: every
    gait goes out as an upload the module validates and compiles, every trial is walked by the
    module's table, measured by the bridge's IMU odometry, and the run ends on the best gait.
    """
    from hexapod_msgs.msg import ServoFailure
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from std_srvs.srv import SetBool, Trigger

    path = _preset_archive(tmp_path)
    emu, radio, imu = _emulated_robot(
        launch,
        tmp_path,
        '--sim',
        '--imu-noise',
        '--seed',
        '4',
        '--firmware',
        'native',
        '--dead-servo',
        '3',
        '--dead-servo',
        '12',
    )
    bridge = launch('hexapod_bridge', 'bridge_node', params={'port': radio, 'imu_port': imu})
    node = launch(
        'hexapod_adapt',
        'adapt_node',
        params={'archive': str(path), 'mode': 'robot', 'record_dir': ''},
    )
    failures = ros.collect(
        ServoFailure,
        'servo_failures',
        QoSProfile(
            depth=64,
            durability=DurabilityPolicy.TRANSIENT_LOCAL,
            reliability=ReliabilityPolicy.RELIABLE,
        ),
    )
    trials = ros.collect(AdaptationTrial, 'adapt/trials', 10)
    assert ros.call(SetBool, 'bridge_node/arm', SetBool.Request(data=True)).success
    # before any trial: HELLO, and the module's health check names both dead servos
    check = ros.call(Trigger, 'bridge_node/check_servos', Trigger.Request())
    assert check.success and 'protocol 1.1' in check.message, check.message
    wait_for(lambda: {f.servo_id for f in failures} == {3, 12}, 20, 'servo failure reports')
    before = len(failures)
    response = ros.adapt(Adapt.Goal(max_trials=3, alpha=1.0), timeout=180)
    assert response.trials >= 1, response.message
    _every_trial_measured_within_the_stated_accuracy(emu, trials, response.trials)
    best = max(trials, key=lambda t: t.measured_speed)
    assert response.best_archive_index == best.archive_index
    assert response.best_speed == pytest.approx(best.measured_speed)
    # and again after each walk, on the right legs
    wait_for(lambda: len(failures) >= before + 2, 20, 'reports after the walks')
    assert {(f.servo_id, f.leg, f.joint) for f in failures} == {(3, 1, 'femur'), (12, 4, 'femur')}
    assert node.alive() and bridge.alive() and emu.alive()


@pytest.mark.slow
def test_manual_mode_takes_the_operators_distance(ros, launch, tmp_path, small_archive):
    """
    The tape-measure workflow: the walk is started through the bridge, then the operator reports.

    A distance is refused with no trial waiting; the prompt comes in the feedback; the console
    command ``report_distance`` answers it; 0.0 m (a damaged robot that did not move) ends the
    trial at once.
    """
    import subprocess
    import time

    from hexapod_msgs.srv import ReportDistance
    from std_srvs.srv import SetBool

    path, archive, _ = small_archive
    _emu, radio, _imu = _emulated_robot(launch, tmp_path)
    launch('hexapod_bridge', 'bridge_node', params={'port': radio})
    launch(
        'hexapod_adapt',
        'adapt_node',
        params={'archive': str(path), 'mode': 'manual', 'record_dir': ''},
    )
    trials = ros.collect(AdaptationTrial, 'adapt/trials', 10)
    early = ros.call(
        ReportDistance, 'adapt_node/report_distance', ReportDistance.Request(distance=1.0)
    )
    assert not early.accepted and 'no manual trial' in early.message
    assert ros.call(SetBool, 'bridge_node/arm', SetBool.Request(data=True)).success
    run = ros.send_adapt(Adapt.Goal(max_trials=2))

    def prompts() -> int:
        return sum('report_distance' in f.note for f in run.feedback)

    wait_for(lambda: prompts() == 1, 60, 'the prompt in the feedback, once the walk ended')
    silly = ros.call(
        ReportDistance, 'adapt_node/report_distance', ReportDistance.Request(distance=float('nan'))
    )
    assert not silly.accepted and 'not a plausible' in silly.message
    command = WS / 'install' / 'hexapod_adapt' / 'lib' / 'hexapod_adapt' / 'report_distance'
    said = subprocess.run(
        [str(command), '0.62'], capture_output=True, text=True, timeout=60,
        stdin=subprocess.DEVNULL,
    )  # fmt: skip
    assert said.returncode == 0 and '0.620 m recorded' in said.stdout, said.stdout + said.stderr
    # the second trial, reported as 0.0 m: it ends at once
    wait_for(lambda: prompts() == 2, 60, 'the second prompt')
    zero = ros.call(
        ReportDistance, 'adapt_node/report_distance', ReportDistance.Request(distance=0.0)
    )
    assert zero.accepted, zero.message
    answered = time.monotonic()
    wait_for(lambda: len(trials) == 2, 10, 'the second trial message')
    assert time.monotonic() - answered < 1.0
    wait_for(run.done, 30, 'the adaptation to finish')
    assert run.result().trials == 2
    assert trials[0].measured_speed == pytest.approx(0.62 / 5.0)
    assert trials[1].measured_speed == 0.0
    # nothing waits for a distance any more: refused, with the reason, exit status 1
    late = subprocess.run(
        [str(command), '0.3'], capture_output=True, text=True, timeout=60,
        stdin=subprocess.DEVNULL,
    )  # fmt: skip
    assert late.returncode == 1 and 'no manual trial is waiting' in late.stderr, late.stderr


@pytest.mark.slow
def test_a_second_goal_is_rejected_and_ctrl_c_mid_run_finishes_the_recording(
    ros, launch, tmp_path, small_archive
):
    from mcap.reader import make_reader
    from std_srvs.srv import SetBool

    path, _archive, _ = small_archive
    _emu, radio, _imu = _emulated_robot(launch, tmp_path)
    launch('hexapod_bridge', 'bridge_node', params={'port': radio})
    node = launch(
        'hexapod_adapt',
        'adapt_node',
        params={'archive': str(path), 'mode': 'manual', 'record_dir': str(tmp_path / 'runs')},
    )
    assert ros.call(SetBool, 'bridge_node/arm', SetBool.Request(data=True)).success
    assert ros.send_adapt(Adapt.Goal(max_trials=3)).handle().accepted
    wait_for(
        lambda: 'report it: report_distance' in node.log(), 30, 'a trial waiting for the operator'
    )
    busy = ros.send_adapt(Adapt.Goal(max_trials=1))
    assert not busy.handle().accepted  # rejected, and the node says why
    wait_for(lambda: BUSY in node.log(), 10, 'the reason for the rejection in the log')
    assert node.stop() == 0
    files = list((tmp_path / 'runs').glob('*.mcap'))
    assert len(files) == 1
    with open(files[0], 'rb') as f:
        assert make_reader(f).get_summary() is not None  # finished cleanly: index and footer
    # the run so far: one gait sent, no trial completed (sensor topics are recorded beside them)
    run_topics = [
        t for t, _, _ in read_messages(files[0]) if t in ('/gait/parameters', '/adapt/trials')
    ]
    assert run_topics == ['/gait/parameters']


@pytest.mark.slow
def test_a_gait_the_robot_refuses_stops_the_run_with_the_robots_reason(ros, launch, tmp_path):
    from hexapod_gait.trajectory import reachable_key_points
    from std_srvs.srv import SetBool

    rng = np.random.default_rng(5)
    genes = next(g for g in rng.random((1000, 32)) if not reachable_key_points(g[None])[0])
    unreachable = Archive(
        np.full((1, 6), 0.5),
        np.array([1.0]),
        np.full((1, 6), 0.5),
        genes[None],
        {'seed': 0, 'evaluations': 1, **simulation_fingerprint('pybullet')},
    ).save(tmp_path / 'bad.npz')
    _emu, radio, _imu = _emulated_robot(launch, tmp_path)
    launch('hexapod_bridge', 'bridge_node', params={'port': radio})
    node = launch(
        'hexapod_adapt',
        'adapt_node',
        # no diagnosis: its safety model would veto the gait before the robot could refuse it
        params={'archive': str(unreachable), 'mode': 'robot', 'record_dir': '', 'diagnose': False},
    )
    assert ros.call(SetBool, 'bridge_node/arm', SetBool.Request(data=True)).success
    response = ros.adapt(Adapt.Goal(max_trials=3), timeout=120)
    assert not response.success and response.trials == 0
    assert 'trial 1 aborted' in response.message and 'UNREACHABLE' in response.message
    assert node.alive()


@pytest.mark.slow
def test_bad_servo_reports_are_refused_and_the_node_lives(ros, launch, domain_id):
    from hexapod_msgs.msg import ServoFailure
    from std_srvs.srv import Trigger

    # the test's node plays the bridge adapt_node is configured to believe
    params = {'mode': 'robot', 'record_dir': '', 'bridge_node': 'test_harness'}
    node = launch('hexapod_adapt', 'adapt_node', params=params)
    report = ros.play_bridge()
    for servo, leg in [(40, 0), (3, 1), (3, 1), (12, 4), (8, 3)]:
        report(ServoFailure(servo_id=servo, robot_leg=leg, leg=leg, joint='femur'))
    wait_for(lambda: 'name 3 failed legs' in node.log(), 20, 'the third leg refused')
    log = node.log()
    assert 'servo 40 reported dead names no leg (leg 0)' in log
    assert 'servo 3 (leg 1) reported dead again: already known' in log
    assert 'servo 12 reported dead: leg 4 femur unpowered' in log
    forgers_are_ignored_and_named(node, domain_id)
    # forget drops what the bridge reported (after a repair), and the forgers' were never taken
    forget = ros.call(Trigger, 'adapt_node/forget', Trigger.Request())
    assert forget.success and 'forgot the reports of dead servos [3, 8, 12]' in forget.message
    again = ros.call(Trigger, 'adapt_node/forget', Trigger.Request())
    assert again.success and again.message == 'no servo reports to forget'
    assert node.alive()


@pytest.mark.slow
def test_a_rogue_status_publisher_cannot_confirm_an_upload(ros, launch, small_archive):
    """
    Only bridge_node's ~/upload_gait answer confirms an upload.

    Status texts that look like a confirmation (from any publisher, or radio text the bridge
    reposts) do not.
    """
    from diagnostic_msgs.msg import DiagnosticStatus

    path, archive, _ = small_archive
    node = launch(
        'hexapod_adapt',
        'adapt_node',
        params={'archive': str(path), 'mode': 'robot', 'record_dir': '', 'trial_timeout': 3.0},
    )
    rogue = ros.node.create_publisher(DiagnosticStatus, 'bridge/status', status_log_qos())
    for niche in archive.elite_indices():
        rogue.publish(
            DiagnosticStatus(
                level=DiagnosticStatus.OK,
                name='bridge_node',
                message=f'gait uploaded (archive index {niche})',
            )
        )
    trials = ros.collect(AdaptationTrial, 'adapt/trials', 10)
    response = ros.adapt(Adapt.Goal(max_trials=2), timeout=60)
    assert not response.success and response.trials == 0 and not trials
    assert 'upload_gait is not available' in response.message
    assert node.alive()
