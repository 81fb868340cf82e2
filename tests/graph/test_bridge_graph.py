# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""bridge_node and its lifecycle against robot_emulator over pseudo-terminals."""

from __future__ import annotations

import json
import math
import os
import signal
import time

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from hexapod_bridge.emulator.robot_emulator_cli import radio_gone_times
from hexapod_bridge.odometry import SPEED_ACCURACY
from hexapod_bridge.ros_conversions import reports_down_since
from hexapod_gait import preset
from hexapod_gait.ros_conversions import gait_to_msg
from hexapod_msgs.msg import GaitParameters as GaitParametersMsg
from hexapod_msgs.msg import LinkStatus
from hexapod_util.ros_glue import EVENTS
from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState, GetState
from nav_msgs.msg import Odometry
import numpy as np
import pytest
from rclpy.qos import DurabilityPolicy, qos_profile_sensor_data, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import Imu, JointState
from std_srvs.srv import SetBool, Trigger

from conftest import status_log_qos, wait_for

pytestmark = pytest.mark.ros
LATCHED = QoSProfile(
    depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE
)


def _emulator(launch, tmp_path, *extra):
    radio, imu = str(tmp_path / 'radio'), str(tmp_path / 'imu')
    emu = launch(
        'hexapod_bridge', 'robot_emulator', args=['--radio-link', radio, '--imu-link', imu, *extra]
    )
    wait_for(lambda: os.path.exists(radio) and os.path.exists(imu), 60, 'emulator ports')
    return emu, radio, imu


@pytest.mark.slow
@pytest.mark.parametrize('firmware', ['python', 'native'])
def test_upload_and_trial_end_to_end_over_pseudo_terminals(ros, launch, tmp_path, firmware):
    emu, radio, imu = _emulator(
        launch, tmp_path, '--sim', '--imu-noise', '--seed', '7', '--firmware', firmware
    )
    bridge = launch('hexapod_bridge', 'bridge_node', params={'port': radio, 'imu_port': imu})
    status = ros.collect(DiagnosticStatus, 'bridge/status', status_log_qos())
    reliable = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
    odom, trial_odom = (
        ros.collect(Odometry, 'odom', reliable),
        ros.collect(Odometry, 'trial_odom', reliable),
    )
    assert ros.call(SetBool, 'bridge_node/arm', SetBool.Request(data=True)).success
    pub = ros.node.create_publisher(GaitParametersMsg, 'gait/parameters', LATCHED)
    gait = preset('quadruped').replace(archive_index=31)
    pub.publish(gait_to_msg(gait))
    wait_for(
        lambda: any('gait uploaded (archive index 31)' in s.message for s in status), 30, 'upload'
    )
    time.sleep(1.0)  # the robot stands still before the trial
    response = ros.call(Trigger, 'bridge_node/start_trial', Trigger.Request())
    assert response.success, response.message
    wait_for(lambda: trial_odom, 30, 'trial odometry')
    o = trial_odom[-1].pose.pose.position
    bridge_speed = (o.x * math.cos(gait.crab_angle) + o.y * math.sin(gait.crab_angle)) / 5.0
    wait_for(lambda: 'TRIAL ' in emu.log(), 10, 'emulator trial report')
    truth = json.loads(emu.log().split('TRIAL ', 1)[1].splitlines()[0])
    print(f'bridge odom {bridge_speed:.4f} m/s vs simulator {truth["speed"]:.4f} m/s')
    assert truth['state'] == 'done' and abs(bridge_speed - truth['speed']) <= SPEED_ACCURACY
    # odom is continuous (REP 105): from the origin, it ends the first trial where the trial did
    wait_for(lambda: odom[-1].pose.pose.position.x == o.x, 5, 'odom at the end of the trial')
    assert odom[-1].pose.pose.position.y == o.y and odom[-1].header.frame_id == 'odom'
    assert bridge.alive() and emu.alive()


def test_servo_failure_reports_are_published_with_their_leg_and_bad_ones_are_not(
    ros, launch, tmp_path
):
    import pty
    import tty

    from hexapod_msgs.msg import ServoFailure

    master, slave = pty.openpty()
    tty.setraw(master)
    tty.setraw(slave)
    link = tmp_path / 'radio'
    os.symlink(os.ttyname(slave), link)
    # the robot's leg 2 is URDF leg 6 under the mirrored numbering
    bridge = launch(
        'hexapod_bridge', 'bridge_node', params={'port': str(link), 'leg_map': [1, 6, 5, 4, 3, 2]}
    )
    failures = ros.collect(ServoFailure, 'servo_failures', EVENTS)
    status = ros.collect(DiagnosticStatus, 'bridge/status', status_log_qos())
    link_status = ros.collect(LinkStatus, 'bridge_node/link_status', 10)
    wait_for(lambda: any(m.connected for m in link_status), 30, 'the bridge on the port')
    try:
        # servo 0x40 does not exist (ids 2..19): logged, no leg marked; then servo 5, twice
        os.write(master, bytes([0xFF, 0xFD, 0x0B, 0x40, 0xFF, 0xFD, 0x0B, 0x05]))
        wait_for(lambda: failures, 20, 'a servo failure report')
        os.write(master, bytes([0xFF, 0xFD, 0x0B, 0x05]))
        wait_for(lambda: len(failures) == 2, 20, 'the repeated report')
        time.sleep(0.5)
        assert [(f.servo_id, f.robot_leg, f.leg, f.joint) for f in failures] == [
            (5, 2, 6, 'coxa'),
            (5, 2, 6, 'coxa'),
        ]
        assert failures[0].header.stamp.sec > 0
        assert any('servo 5 (coxa of leg 6, robot leg 2)' in s.message for s in status)
        assert bridge.alive()
    finally:
        os.close(master)
        os.close(slave)


def test_diagnostics_name_every_servo_the_link_and_the_imu_and_a_dead_servo_turns_error(
    ros, launch, tmp_path
):
    """/diagnostics (DiagnosticArray): 18 servos by their URDF joint, the radio, the IMU."""
    import pty
    import tty

    from diagnostic_msgs.msg import DiagnosticArray
    from hexapod_msgs.msg import ServoFailure

    master, slave = pty.openpty()
    tty.setraw(master)
    tty.setraw(slave)
    link = tmp_path / 'radio'
    os.symlink(os.ttyname(slave), link)
    bridge = launch(
        'hexapod_bridge', 'bridge_node', params={'port': str(link), 'leg_map': [1, 6, 5, 4, 3, 2]}
    )
    arrays = ros.collect(DiagnosticArray, '/diagnostics', 10)
    failures = ros.collect(ServoFailure, 'servo_failures', EVENTS)

    def statuses(array) -> dict:
        return {st.name.split(': ', 1)[1]: st for st in array.status}

    try:

        def connected() -> bool:
            link = arrays and statuses(arrays[-1]).get('radio link')
            return bool(link) and link.message.startswith('connected')

        wait_for(connected, 30, 'the bridge connected, on /diagnostics')
        first = statuses(arrays[-1])
        servos = {n: st for n, st in first.items() if '(servo ' in n}
        assert len(servos) == 18 and all(st.level == DiagnosticStatus.OK for st in servos.values())
        # the robot's leg 2 is URDF leg 6 here: servo 5, its coxa, is joint_6_1
        assert servos['joint_6_1 (servo 5)'].hardware_id == 'Dynamixel servo id 5'
        assert first['IMU'].level == DiagnosticStatus.WARN  # no telemetry yet from the pty
        assert first['radio link'].hardware_id.startswith('433 MHz radio on ')
        os.write(master, bytes([0xFF, 0xFD, 0x0B, 0x05]))
        wait_for(lambda: failures, 20, 'the servo failure report')
        reported = failures[0].header.stamp

        def dead_in(array) -> bool:
            st = statuses(array).get('joint_6_1 (servo 5)')
            return st is not None and st.level == DiagnosticStatus.ERROR

        wait_for(lambda: any(dead_in(a) for a in arrays), 5, 'servo 5 ERROR on /diagnostics')
        shown = next(a for a in arrays if dead_in(a)).header.stamp
        delay = (shown.sec - reported.sec) + (shown.nanosec - reported.nanosec) * 1e-9
        print(f'servo 5 ERROR on /diagnostics {delay * 1000:.0f} ms after its report')
        assert 0 <= delay <= 1.0
        latest = statuses(arrays[-1])
        others = [st for n, st in latest.items() if '(servo ' in n and n != 'joint_6_1 (servo 5)']
        assert len(others) == 17 and all(st.level == DiagnosticStatus.OK for st in others)
        assert bridge.alive()
    finally:
        os.close(master)
        os.close(slave)


def test_bad_requests_are_refused_with_reasons(ros, launch, tmp_path):
    _emu, radio, _imu = _emulator(launch, tmp_path)
    bridge = launch('hexapod_bridge', 'bridge_node', params={'port': radio})
    status = ros.collect(DiagnosticStatus, 'bridge/status', status_log_qos())
    start = ros.call(Trigger, 'bridge_node/start_trial', Trigger.Request())
    assert not start.success and 'not armed' in start.message
    assert ros.call(SetBool, 'bridge_node/arm', SetBool.Request(data=True)).success
    start = ros.call(Trigger, 'bridge_node/start_trial', Trigger.Request())
    assert not start.success and 'no gait uploaded' in start.message
    pub = ros.node.create_publisher(GaitParametersMsg, 'gait/parameters', LATCHED)
    bad = gait_to_msg(preset('tripod'))
    bad.duty_factor[2] = 1.5
    pub.publish(bad)
    wait_for(
        lambda: any('duty_factor[leg 3]' in s.message for s in status), 20, 'invalid gait refused'
    )
    far = gait_to_msg(preset('tripod').replace(radius=[0.29] * 6))
    seen = len(status)
    pub.publish(far)
    # the refusal may be followed at once by the robot's own "GAIT REJECTED" text: look at every
    # status since
    wait_for(
        lambda: any('UNREACHABLE' in s.message for s in status[seen:]),
        20,
        'unreachable gait refused by the robot',
    )
    stop = ros.call(Trigger, 'bridge_node/emergency_stop', Trigger.Request())
    assert stop.success and 'disarmed' in stop.message
    assert bridge.alive()


def _open_fds(pid: int) -> int:
    return len(os.listdir(f'/proc/{pid}/fd'))


@pytest.mark.slow
def test_port_vanishing_twenty_times(ros, launch, tmp_path):
    emu, radio, _imu = _emulator(launch, tmp_path)
    bridge = launch(
        'hexapod_bridge',
        'bridge_node',
        params={'port': radio, 'arm_on_start': True, 'telemetry_period': 0.2},
    )
    links = ros.collect(LinkStatus, 'bridge_node/link_status', 10)
    imu_times: list[float] = []
    ros.node.create_subscription(
        Imu, 'imu/data', lambda m: imu_times.append(time.monotonic()), qos_profile_sensor_data
    )
    wait_for(lambda: imu_times, 30, 'first attitude telemetry')
    time.sleep(1.0)
    fds_before = _open_fds(bridge.proc.pid)
    rng = np.random.default_rng(20)
    down_latency, up_latency = [], []
    for cycle in range(20):
        gone_for = float(rng.uniform(1.0, 10.0))
        t_gone_wall = time.time()
        emu.proc.send_signal(signal.SIGUSR1)
        # latencies count from the port's change, not the signal: a loaded emulator acts on its
        # signals only between steps of its simulation (it prints when, on CLOCK_MONOTONIC)
        t_gone = wait_for(
            lambda: dict(enumerate(radio_gone_times(emu.log()))).get(cycle),
            10,
            'the emulator to drop the port',
        )
        # a LinkStatus stamped after the loss that says "not connected"
        wait_for(
            lambda: links and reports_down_since(links[-1], t_gone_wall),
            5,
            f'link-down report, cycle {cycle}',
        )
        down_latency.append(time.monotonic() - t_gone)
        time.sleep(max(0.0, gone_for - (time.monotonic() - t_gone)))
        emu.proc.send_signal(signal.SIGUSR2)
        wait_for(
            lambda: emu.log().count('RADIO /') > cycle + 1, 10, 'the emulator to restore the port'
        )
        t_back = time.monotonic()
        wait_for(
            lambda: imu_times and imu_times[-1] > t_back,
            5,
            f'publishing after the port returned, cycle {cycle}',
        )
        up_latency.append(time.monotonic() - t_back)
        assert bridge.alive(), f'bridge_node exited in cycle {cycle}'
    time.sleep(6.0)  # connected again: keep-alives must get through
    fds_after = _open_fds(bridge.proc.pid)
    emu.stop()
    pings = [
        int(line.split('pings=')[1].split()[0])
        for line in emu.log().splitlines()
        if line.startswith('STATS')
    ]
    pings_after_last_return = pings[-1] - pings[-2]
    print(
        f'20 port losses: link-down reported after max {max(down_latency):.2f} s, publishing'
        f' resumed after max {max(up_latency):.2f} s; open file descriptors {fds_before} ->'
        f' {fds_after}; robot received {pings_after_last_return} keep-alives in the 6 s after the'
        ' last return'
    )
    # each within its wait's 5 s; how fast is a benchmark (make bench-bridge: bridge_link_*_ms)
    assert fds_after <= fds_before
    assert len(pings) == 21 and pings_after_last_return >= 4  # 1 per second while armed


def test_after_an_emergency_stop_the_documented_sequence_powers_the_robot_again(
    ros, launch, tmp_path
):
    from hexapod_msgs.srv import UploadGait

    _emu, radio, _imu = _emulator(launch, tmp_path)
    bridge = launch('hexapod_bridge', 'bridge_node', params={'port': radio, 'trial_duration': 1.0})
    assert ros.call(SetBool, 'bridge_node/arm', SetBool.Request(data=True)).success
    upload = ros.call(
        UploadGait,
        'bridge_node/upload_gait',
        UploadGait.Request(gait=gait_to_msg(preset('tripod'))),
        timeout=40,
    )
    assert upload.success and upload.gait_id > 0, upload.message
    assert ros.call(Trigger, 'bridge_node/emergency_stop', Trigger.Request()).success
    # disarmed: nothing is sent, and power cannot be switched on while disarmed
    power = ros.call(SetBool, 'bridge_node/motor_power', SetBool.Request(data=True))
    assert not power.success and 'not armed' in power.message
    assert ros.call(SetBool, 'bridge_node/arm', SetBool.Request(data=True)).success
    refused = ros.call(Trigger, 'bridge_node/start_trial', Trigger.Request(), timeout=30)
    assert not refused.success and 'ESTOPPED' in refused.message  # the robot is still e-stopped
    assert ros.call(SetBool, 'bridge_node/motor_power', SetBool.Request(data=True)).success
    started = ros.call(Trigger, 'bridge_node/start_trial', Trigger.Request(), timeout=30)
    assert started.success, started.message
    assert bridge.alive()


def _link(diagnostics: list) -> list:
    """The radio link's statuses on /diagnostics, oldest first."""
    return [s for a in diagnostics for s in a.status if s.name == 'bridge_node: radio link']


def test_every_lifecycle_transition_and_a_missing_or_vanishing_port(ros, launch, tmp_path):
    radio, imu = str(tmp_path / 'radio'), str(tmp_path / 'imu')
    node = launch('hexapod_bridge', 'bridge_node', params={'port': radio, 'autostart': False})
    diagnostics = ros.collect(DiagnosticArray, '/diagnostics', 50)

    def state() -> str:
        return ros.call(GetState, 'bridge_node/get_state', GetState.Request()).current_state.label

    def change(transition: int) -> bool:
        request = ChangeState.Request(transition=Transition(id=transition))
        return ros.call(ChangeState, 'bridge_node/change_state', request, timeout=30).success

    def trigger(name: str):
        return ros.call(Trigger, f'bridge_node/{name}', Trigger.Request(), timeout=30)

    assert state() == 'unconfigured'
    refused = trigger('start_trial')
    assert not refused.success and 'unconfigured' in refused.message
    # a port that does not exist: configure fails with the reason, the node stays unconfigured
    assert not change(Transition.TRANSITION_CONFIGURE)
    assert state() == 'unconfigured' and node.alive()
    wait_for(lambda: 'configure failed: the radio port' in node.log(), 10, 'the reason logged')
    wait_for(
        lambda: any('No such file' in s.message for s in _link(diagnostics)), 10, 'diagnostics'
    )
    # the port comes: configure again; inactive is silent
    emu = launch(
        'hexapod_bridge',
        'robot_emulator',
        args=['--radio-link', radio, '--imu-link', imu, '--sim'],
    )
    wait_for(lambda: os.path.exists(radio), 60, "the emulator's port")
    assert change(Transition.TRANSITION_CONFIGURE) and state() == 'inactive'
    refused = trigger('start_trial')
    assert not refused.success and 'not armed' in refused.message
    # active: armed, a gait uploaded and a trial walking
    assert change(Transition.TRANSITION_ACTIVATE) and state() == 'active'
    pub = ros.node.create_publisher(GaitParametersMsg, 'gait/parameters', LATCHED)
    pub.publish(gait_to_msg(preset('tripod').replace(archive_index=3)))
    wait_for(lambda: 'gait uploaded' in node.log(), 30, 'the upload')
    joints = ros.collect(JointState, 'joint_states', qos_profile_sensor_data)
    started = trigger('start_trial')
    assert started.success, started.message
    time.sleep(1.5)
    # the legs in 3D: the commanded angles, 18 URDF joints, moving as the robot walks
    assert len(joints) > 10 and len(joints[-1].name) == 18 and joints[-1].name[0] == 'joint_1_1'
    assert len({tuple(j.position) for j in joints[-10:]}) > 1
    # deactivate: the robot stops (its walk ends before its 5 s), the bridge disarms
    assert change(Transition.TRANSITION_DEACTIVATE) and state() == 'inactive'
    wait_for(lambda: 'TRIAL ' in emu.log(), 20, "the emulator's report of the walk")
    walk = json.loads(emu.log().split('TRIAL ', 1)[1].splitlines()[0])
    assert walk['state'] == 'stopped', walk  # not 'done': it did not walk its 5 s
    assert 'inactive: the trial stopped, disarmed' in node.log()
    # cleanup closes the ports; configure and activate work again
    assert change(Transition.TRANSITION_CLEANUP) and state() == 'unconfigured'
    wait_for(lambda: _link(diagnostics)[-1].message.startswith('no link'), 10, 'no link')
    assert change(Transition.TRANSITION_CONFIGURE) and change(Transition.TRANSITION_ACTIVATE)
    assert state() == 'active'
    # the port vanishes while active: the node stays active and says so; it is not a transition
    emu.stop()
    wait_for(lambda: _link(diagnostics)[-1].level == DiagnosticStatus.ERROR, 10, 'the link down')
    assert state() == 'active' and node.alive()
    # shutdown from active: finalized, the node process still answers
    assert change(Transition.TRANSITION_ACTIVE_SHUTDOWN) and state() == 'finalized'
    assert node.alive()
