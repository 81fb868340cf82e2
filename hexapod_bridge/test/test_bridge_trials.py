# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Trial state on the host link.

A trial ends only on the robot's report about THAT trial, with robot reports dropped, duplicated
and garbled (seeded, no ROS; firmware emulator in the loop).
"""

from __future__ import annotations

from hexapod_bridge.emulator.firmware import RobotFirmware
from hexapod_bridge.link import RobotLink
from hexapod_bridge.protocol import extension as ext
from hexapod_bridge.protocol.stream import HostParser
from hexapod_gait import preset
import numpy as np
import pytest

STEP = 0.001


def _is_trial_report(frame: bytes) -> bool:
    decoded = HostParser().feed(frame)
    return (
        len(decoded) == 1
        and isinstance(decoded[0], ext.ReportFrame)
        and decoded[0].type == ext.Report.TRIAL
    )


class Bench:
    """
    Host link and emulated robot over an ideal wire, except for the TRIAL reports.

    The robot->host TRIAL reports pass through ``mangle`` (drop: return b""; duplicate;
    garble).
    """

    def __init__(self, mangle) -> None:
        self.link, self.fw, self.t = RobotLink(), RobotFirmware(walk_duration=5.0), 0.0
        self.mangle = mangle
        self.link.arm(True, 0.0)
        self.ended: list[tuple[int, ext.TrialState, float]] = []  # (generation, state, host time)

    def run_until(self, done, limit: float) -> None:
        end = self.t + limit
        while not done() and self.t < end:
            self.tick()

    def tick(self) -> None:
        self.t += STEP
        for frame in self.link.poll(self.t):
            self.fw.receive(frame, self.t)
        radio, _ = self.fw.advance(self.t)
        out = bytearray()
        for frame in HostParserSplitter.split(radio):
            out += self.mangle(frame) if _is_trial_report(frame) else frame
        before = (self.link.trial_generation, self.link.trial_state)
        self.link.receive(bytes(out), self.t)
        after = (self.link.trial_generation, self.link.trial_state)
        if after != before and after[1] in (ext.TrialState.DONE, ext.TrialState.STOPPED):
            self.ended.append((after[0], after[1], self.t))

    def upload_and_start(self, gait_index: int) -> float:
        op = self.link.upload(preset('tripod').replace(archive_index=gait_index))
        self.run_until(lambda: op.done, 10.0)
        assert op.ok, op.message
        start = self.link.start_trial(5.0, op.result['gait_id'])
        self.run_until(lambda: start.done, 5.0)
        assert start.ok, start.message
        return self.t


class HostParserSplitter:
    """
    Split a robot->host byte string into frames as the robot wrote them.

    The emulator emits whole frames; this re-parses to find their boundaries.
    """

    @staticmethod
    def split(data: bytes) -> list[bytes]:
        frames, i = [], 0
        while i < len(data):
            for j in range(i + 1, len(data) + 1):
                if HostParser().feed(data[i:j]):
                    frames.append(data[i:j])
                    i = j
                    break
            else:
                frames.append(data[i:])
                break
        return frames


def _drop_walking(frame: bytes) -> bytes:
    return b'' if frame[3] == ext.TrialState.WALKING else frame


@pytest.mark.parametrize(
    'name,mangle',
    [
        ('walking report dropped', _drop_walking),
        ('every report duplicated', lambda f: f + f),
        (
            'walking dropped, done duplicated',
            lambda f: b'' if f[3] == ext.TrialState.WALKING else f + f,
        ),
        (
            'walking report garbled',
            lambda f: (
                f[:4] + bytes([f[4] ^ 0x5A]) + f[5:] if f[3] == ext.TrialState.WALKING else f
            ),
        ),
    ],
)
def test_a_trial_ends_only_on_its_own_done_report(name, mangle):
    bench = Bench(mangle)
    for k in range(3):  # back-to-back trials: stale DONEs are the risk
        started = bench.upload_and_start(k)
        generation = bench.link.trial_generation
        assert bench.link.trial_state is ext.TrialState.WALKING, name
        bench.run_until(lambda: bench.link.trial_state is ext.TrialState.DONE, 8.0)
        assert bench.link.trial_state is ext.TrialState.DONE, name
        ends = [e for e in bench.ended if e[0] == generation]
        assert ends, name
        # it ended when the robot finished this walk, not at the previous trial's stale report
        assert ends[0][2] - started == pytest.approx(5.0, abs=0.15), (name, ends[0][2] - started)
        assert bench.fw.trials[-1].state == 'done'


def test_a_report_in_flight_from_the_previous_trial_is_not_taken_for_the_new_one():
    link = RobotLink()
    link.arm(True, 0.0)
    link.trial_state = ext.TrialState.DONE  # what the previous trial left behind
    link.start_trial(5.0, 1)
    assert link.trial_state is ext.TrialState.IDLE
    # the previous trial's DONE report, duplicated, arrives before the robot acknowledges the start
    stale = ext.encode_report(
        ext.Report.TRIAL, 9, bytes([ext.TrialState.DONE]) + (5000).to_bytes(3, 'big')
    )
    link.receive(stale + stale, 0.1)
    assert link.trial_state is ext.TrialState.IDLE and link.stats.stale_reports == 2
    assert link.trial_generation == 0


def test_a_noisy_stream_never_ends_a_trial_with_another_trials_report():
    """
    A trial end the host sees is always the robot's end of that very trial.

    Every robot->host frame is dropped, duplicated, garbled or followed by garbage at random
    (seeded): uploads and starts may need retries or fail, but whenever the host sees a trial
    end, it is the robot's end of that very trial (5 s after its start).
    """
    rng = np.random.default_rng(11)

    def mangle_any(frame: bytes) -> bytes:
        u = rng.random()
        if u < 0.05:
            return b''
        if u < 0.10:
            return frame + frame
        if u < 0.15:
            i = int(rng.integers(len(frame)))
            return (
                frame[:i]
                + bytes([frame[i] ^ int(rng.integers(1, 256))])
                + frame[slice(i + 1, None)]
            )
        if u < 0.20:
            return (
                frame + rng.integers(0, 256, int(rng.integers(1, 12))).astype(np.uint8).tobytes()
            )
        return frame

    bench = Bench(lambda f: f)
    bench.mangle = mangle_any
    original_tick = bench.tick

    def tick_all_frames() -> None:  # mangle every frame, not only TRIAL reports
        bench.t += STEP
        for frame in bench.link.poll(bench.t):
            bench.fw.receive(frame, bench.t)
        radio, _ = bench.fw.advance(bench.t)
        out = b''.join(mangle_any(f) for f in HostParserSplitter.split(radio))
        before = (bench.link.trial_generation, bench.link.trial_state)
        bench.link.receive(out, bench.t)
        after = (bench.link.trial_generation, bench.link.trial_state)
        if after != before and after[1] in (ext.TrialState.DONE, ext.TrialState.STOPPED):
            bench.ended.append((after[0], after[1], bench.t))

    bench.tick = tick_all_frames
    starts: dict[int, float] = {}
    completed = 0
    for k in range(6):
        op = bench.link.upload(preset('tripod').replace(archive_index=k))
        bench.run_until(lambda: op.done, 30.0)
        if not op.ok:
            continue
        start = bench.link.start_trial(5.0, op.result['gait_id'])
        bench.run_until(lambda: start.done, 10.0)
        if not start.ok:
            bench.run_until(lambda: False, 6.0)  # the robot may be walking anyway: let it finish
            continue
        starts[bench.link.trial_generation] = bench.t
        bench.run_until(lambda: bench.link.trial_state is ext.TrialState.DONE, 8.0)
        bench.run_until(lambda: False, 0.5)
        completed += 1
    assert completed >= 3 and original_tick is not None
    for generation, state, t in bench.ended:
        assert generation in starts and state is ext.TrialState.DONE
        assert t - starts[generation] == pytest.approx(5.0, abs=0.3), (
            generation,
            t - starts[generation],
        )
    print(
        f'{completed} trials completed; {len(bench.ended)} ends seen; stale reports'
        f' {bench.link.stats.stale_reports}'
    )


def test_the_commanded_joints_follow_the_uploaded_gait_cycle():
    """joint_states on the robot: the gait's joint table, row by time into the walk."""
    from hexapod_bridge.commanded import CommandedJoints
    from hexapod_gait import preset
    from hexapod_gait.trajectory import build_joint_table

    commanded = CommandedJoints()
    assert commanded.positions(None) is None and commanded.positions(1.0) is None  # no gait
    gait = preset('tripod')
    commanded.set_gait(gait)
    table = build_joint_table(gait)
    assert (commanded.positions(None) == table.positions[0]).all()  # standing
    quarter = gait.period / 4
    assert (commanded.positions(quarter) == table.positions[int(quarter * table.rate)]).all()
    # one cycle later, the same angles; in between, others
    assert (commanded.positions(quarter + gait.period) == commanded.positions(quarter)).all()
    assert (commanded.positions(quarter) != commanded.positions(None)).any()
