# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The base station without ROS: bridge_node's logic against the robot emulator over real ptys.

``robot_emulator`` runs as its own process (PyBullet robot, Xsens on a second pty); the
:class:`BaseStation` here uploads a gait, refuses what it must, runs a trial and reports it.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import random
import signal
import subprocess
import sys
import time

from hexapod_bridge.odometry import STEADY_GAIT_ACCURACY
from hexapod_bridge.station import (
    BAD_FRAME_RATE,
    BaseStation,
    IMU_SILENT_S,
    LINK_LOST_S,
    OVERDUE_S,
    RETRYABLE_FAULTS,
    StationConfig,
    TrialFault,
)
from hexapod_gait import preset
import pytest


def _until(predicate, timeout: float, what: str):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(0.01)
    raise AssertionError(f'timed out after {timeout:g} s waiting for {what}')


@pytest.fixture
def emulator(tmp_path):
    with _emulator_process(tmp_path) as (radio, imu, log, _proc):
        yield radio, imu, log


@contextlib.contextmanager
def _emulator_process(tmp_path):
    radio, imu = tmp_path / 'radio', tmp_path / 'imu'
    log = open(tmp_path / 'emulator.log', 'w')
    proc = subprocess.Popen(
        [
            sys.executable,
            '-m',
            'hexapod_bridge.emulator.robot_emulator_cli',
            '--radio-link',
            str(radio),
            '--imu-link',
            str(imu),
            '--sim',
        ],
        stdout=log,
        stderr=subprocess.STDOUT,
        env=dict(os.environ, PYTHONUNBUFFERED='1'),
    )
    try:
        _until(lambda: radio.exists() and imu.exists(), 60, 'the emulator ports')
        yield radio, imu, tmp_path / 'emulator.log', proc
    finally:
        proc.send_signal(signal.SIGCONT)
        proc.send_signal(signal.SIGINT)
        proc.wait(30)
        log.close()


def test_a_trial_through_the_station_measures_what_the_robot_walked(emulator):
    radio, imu, log = emulator
    lost: list[bool] = []
    station = BaseStation(
        StationConfig(port=str(radio), imu_port=str(imu)),
        on_connection=lambda up, why: lost.append(not up),
    )
    station.start()
    try:
        assert station.start_trial() == (False, 'not armed: call ~/arm first')
        station.arm(True)
        assert station.start_trial() == (
            False,
            'no gait uploaded yet: publish gait/parameters first',
        )
        gait = preset('tripod').replace(crab_angle=0.5)
        op = station.upload(gait)
        assert station.wait(op, 20) and op.ok, op.message
        station.uploaded(op, gait)
        time.sleep(1.0)  # the robot takes the gait's first pose, then stands still
        ok, message = station.start_trial()
        assert ok, message
        assert station.start_trial() == (False, 'a trial is already running')
        result = _until(lambda: station.finished_trial(time.monotonic()), 30, 'the trial')
        assert result.state == 'DONE' and result.problem == '' and result.duration == 5.0
        truth = json.loads(
            next(line for line in log.read_text().splitlines() if line.startswith('TRIAL '))[6:]
        )
        assert abs(result.estimate.speed - truth['speed']) <= STEADY_GAIT_ACCURACY
        # the displacement in the start frame points along the gait's walking direction
        along = result.x * math.cos(0.5) + result.y * math.sin(0.5)
        assert along == pytest.approx(result.estimate.distance, abs=1e-9)
        snap = station.snapshot(time.monotonic())
        assert snap.connected and snap.armed and snap.frames_ok > 0 and not any(lost)
    finally:
        station.stop()


def test_a_settled_trial_walks_the_settling_and_times_only_the_rest(emulator):
    radio, imu, log = emulator
    station = BaseStation(
        StationConfig(port=str(radio), imu_port=str(imu), trial_settle=1.0, trial_duration=2.0)
    )
    station.start()
    try:
        station.arm(True)
        gait = preset('tripod').replace(crab_angle=0.5)
        op = station.upload(gait)
        assert station.wait(op, 20) and op.ok, op.message
        station.uploaded(op, gait)
        time.sleep(1.0)
        ok, message = station.start_trial()
        assert ok and '1 s of settling, then 2 s timed' in message, message
        result = _until(lambda: station.finished_trial(time.monotonic()), 30, 'the trial')
        assert result.state == 'DONE' and result.problem == '' and result.duration == 2.0
        truth = json.loads(
            next(line for line in log.read_text().splitlines() if line.startswith('TRIAL '))[6:]
        )
        assert truth['duration'] == 3.0  # the robot walked the settling and the timed part
        # the pose is the whole walk, the speed (and the twist) the timed part's
        along = result.x * math.cos(0.5) + result.y * math.sin(0.5)
        assert abs(along - truth['distance']) <= STEADY_GAIT_ACCURACY * 3.0
        assert result.vx * math.cos(0.5) + result.vy * math.sin(0.5) == pytest.approx(
            result.estimate.speed, abs=1e-9
        )
        # a steady tripod walks its whole-walk mean speed in the timed part too
        assert abs(result.estimate.speed - truth['speed']) <= STEADY_GAIT_ACCURACY
        assert result.estimate.distance == pytest.approx(result.estimate.speed * 2.0)
        assert result.walk == 3.0
    finally:
        station.stop()


def test_without_an_imu_a_finished_trial_says_so(emulator):
    radio, _imu, _log = emulator
    station = BaseStation(StationConfig(port=str(radio), arm_on_start=True))
    station.start()
    try:
        op = station.upload(preset('tripod'))
        assert station.wait(op, 20) and op.ok, op.message
        station.uploaded(op, preset('tripod'))
        assert station.start_trial()[0]
        result = _until(lambda: station.finished_trial(time.monotonic()), 30, 'the trial')
        assert result.estimate is None and result.problem == 'no IMU configured'
    finally:
        station.stop()


def test_a_port_that_is_not_there_is_reported_not_raised(tmp_path):
    station = BaseStation(StationConfig(port=str(tmp_path / 'nothing'), arm_on_start=True))
    station.start()
    try:
        snap = _until(
            lambda: (s := station.snapshot(time.monotonic())).last_error and s,
            10,
            'the first attempt to open the port',
        )
        assert not snap.connected and 'nothing' in snap.last_error
        assert math.isinf(snap.seconds_since_heard)
    finally:
        station.stop()


def test_a_port_that_does_not_exist_is_told_once_with_its_reason(tmp_path):
    told = []
    station = BaseStation(
        StationConfig(port=str(tmp_path / 'no_such_port')),
        on_connection=lambda up, why: told.append((up, why)),
    )
    station.start()
    try:
        _until(lambda: told, 10, 'the reason the port did not open')
        time.sleep(1.5)  # the radio thread keeps retrying: the same reason is not told again
    finally:
        station.stop()
    assert len(told) == 1, told
    up, why = told[0]
    assert not up and 'no_such_port' in why and 'cannot open' in why


def _walking_station(radio, imu, **config) -> BaseStation:
    """Return a station armed, with the tripod uploaded, standing still, ready for a trial."""
    station = BaseStation(StationConfig(port=str(radio), imu_port=str(imu), **config))
    station.start()
    station.arm(True)
    gait = preset('tripod')

    def acknowledged():  # CI once saw an emulator just started leave all 7 attempts unanswered
        op = station.upload(gait)
        return station.wait(op, 20) and op.ok and op

    op = _until(acknowledged, 60, 'an acknowledged upload')
    station.uploaded(op, gait)
    time.sleep(1.0)
    return station


@pytest.mark.slow
@pytest.mark.parametrize(
    'fault, signals, within',
    [
        # the radio port vanishes (the emulator's SIGUSR1), and comes back (SIGUSR2)
        ('port', (signal.SIGUSR1, signal.SIGUSR2), 1.0),
        # the whole robot falls silent (its process stopped: no radio, no IMU), then goes on
        ('silence', (signal.SIGSTOP, signal.SIGCONT), LINK_LOST_S + 0.5),
        # the robot's microcontroller restarts mid-walk (SIGHUP): it forgets the walk
        ('restart', (signal.SIGHUP, None), IMU_SILENT_S + 0.5),
    ],
)
def test_a_trial_cut_by_a_fault_is_never_scorable_and_ends_within_seconds(
    tmp_path, fault, signals, within
):
    cut, restore = signals
    with _emulator_process(tmp_path) as (radio, imu, _log, proc):
        station = _walking_station(radio, imu)
        try:
            # as the next start below: ci28 once saw an emulator just started on a loaded machine
            # leave all 7 attempts of a first start unanswered; this test is of the faults after it
            _until(lambda: station.start_trial()[0], 20, 'the first start')
            time.sleep(1.5)
            proc.send_signal(cut)
            cut_at = time.monotonic()
            result = _until(lambda: station.finished_trial(time.monotonic()), 30, 'the trial')
            ended = time.monotonic() - cut_at
            if restore is not None:
                proc.send_signal(restore)
            assert not result.valid and result.fault in RETRYABLE_FAULTS, result
            assert result.problem
            assert ended <= within, (ended, result)
            # the link back, the next trial is walked and measured whole
            if fault == 'restart':  # a restarted robot holds no gait: the host uploads again
                op = station.upload(preset('tripod'))
                assert station.wait(op, 20) and op.ok, op.message
                station.uploaded(op, preset('tripod'))
            _until(
                lambda: station.snapshot(time.monotonic()).seconds_since_heard < 1.0,
                20,
                'the link',
            )
            time.sleep(1.0)
            again = _next_whole_trial(station)
            assert abs(again.estimate.speed) < station.max_speed
        finally:
            station.stop()


def _next_whole_trial(station: BaseStation, tries: int = 3):
    """
    Walk trials until one is measured whole, as adapt_node retries; return it.

    A trial before it may be spoiled, never scored: ci33 saw a loaded machine starve the station
    long enough that the emulator's IMU port dropped samples (a real gap, rightly refused).
    """
    for _ in range(tries):
        time.sleep(0.5)
        _until(lambda: station.start_trial()[0], 20, 'a new start')
        result = _until(lambda: station.finished_trial(time.monotonic()), 30, 'the next trial')
        if result.valid and result.problem == '':
            return result
        assert result.fault in RETRYABLE_FAULTS and result.problem, result
    raise AssertionError(f'no trial of {tries} was measured whole: the last {result}')


def test_a_robot_that_never_reports_the_end_spoils_the_trial(emulator):
    radio, imu, _log = emulator
    station = _walking_station(radio, imu, trial_duration=1.0)
    try:
        assert station.start_trial()[0]
        with station.lock:  # as if the robot's report of the end were lost on the radio
            station.trial.generation += 1
            started = station.trial.start  # the overdue time counts from the start sent
        result = _until(lambda: station.finished_trial(time.monotonic()), 30, 'the trial')
        assert result.fault is TrialFault.NO_END_REPORT and result.state == 'NO_REPORT'
        assert time.monotonic() - started >= 1.0 + OVERDUE_S
    finally:
        station.stop()


def test_noise_on_the_radio_above_the_bad_frame_rate_is_said_in_last_error(tmp_path):
    import pty
    import tty

    master, slave = pty.openpty()
    tty.setraw(master)
    tty.setraw(slave)
    link = tmp_path / 'radio'
    os.symlink(os.ttyname(slave), link)
    station = BaseStation(StationConfig(port=str(link)))
    station.start()
    try:
        _until(lambda: station.snapshot(time.monotonic()).connected, 10, 'the port')
        quiet = station.snapshot(time.monotonic())
        assert quiet.last_error == '' and quiet.bad_frame_rate == 0.0
        rng = random.Random(7)
        for _ in range(20):  # 2,000 random bytes with frame headers among them
            os.write(
                master, bytes(rng.choice((0xFF, 0xE7, rng.randrange(256))) for _ in range(100))
            )
            time.sleep(0.05)
        noisy = _until(
            lambda: (
                (n := station.snapshot(time.monotonic())).bad_frame_rate > BAD_FRAME_RATE and n
            ),
            10,
            'the bad frames counted',
        )
        assert 'bad frames/s' in noisy.last_error and 'resyncs' in noisy.last_error, noisy
    finally:
        station.stop()
        os.close(master)
        os.close(slave)
