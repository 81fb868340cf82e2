# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""sim_node's physics thread without ROS: its timing, its reports and work between steps."""

from __future__ import annotations

import threading
import time

from hexapod_gait import build_joint_table, preset
from hexapod_sim.damage import Damage
from hexapod_sim.physics.engines import create_simulator
from hexapod_sim.physics.physics_loop import LoopHooks, PhysicsLoop, publish_period_steps
from hexapod_sim.simulator import SimConfig
from hexapod_sim.trajectory_input import CycleTable
import pytest


@pytest.fixture
def loop():
    sim = create_simulator(SimConfig(engine='mujoco'))
    table = build_joint_table(preset('tripod'), rate=1.0 / sim.dt)
    cycle = CycleTable(table.positions, table.velocities, sim.dt)
    events: dict[str, list] = {'state': [], 'clock': [], 'reset': [], 'unstable': []}
    lock = threading.Lock()

    def log(kind):
        def record(t):
            with lock:
                events[kind].append(t)

        return record

    hooks = LoopHooks(log('state'), log('clock'), log('reset'), log('unstable'), lambda e: True)
    physics = PhysicsLoop(sim, cycle, hooks, rtf=0.0, period_steps=4, clock_steps=6)
    physics.events = events
    yield physics
    physics.stop()
    sim.close()


def wait(predicate, timeout=20.0):
    deadline = time.monotonic() + timeout
    while not predicate():
        assert time.monotonic() < deadline, 'timed out'
        time.sleep(0.01)


def test_state_is_reported_every_period_from_the_reset_and_the_clock_with_it(loop):
    loop.start()
    wait(lambda: len(loop.events['state']) > 50)
    loop.stop()
    dt = loop.sim.dt
    states = loop.events['state']
    assert loop.events['reset'] == [0.0] and states[0] == 0.0  # the pose at the reset first
    steps = [round(t / dt) for t in states[1:]]
    assert steps[:5] == [4, 8, 12, 16, 20]
    clocks = {round(t / dt) for t in loop.events['clock']}
    assert {4, 6, 8, 12} <= clocks and 5 not in clocks


def test_work_runs_between_steps_and_a_reset_restarts_the_step_count(loop):
    loop.start()
    wait(lambda: loop.sim_time > 0.5)
    at = loop.call(loop.reset)
    assert at >= 0.5 and loop.events['reset'][-1] == at
    wait(lambda: loop.sim_time > at + 0.1)
    after = [t for t in list(loop.events['state']) if t > at]
    assert round((after[0] - at) / loop.sim.dt) == 4  # counted from the reset
    applied = loop.call(lambda: loop.set_damage(Damage.lifted([1])))
    assert applied.failed_legs == (1,)
    began = loop.call(lambda: loop.play(loop.cycle))
    assert began >= at


def test_an_error_in_the_work_comes_back_to_the_caller(loop):
    loop.start()

    def broken():
        raise ValueError('bad damage')

    with pytest.raises(ValueError, match='bad damage'):
        loop.call(broken)
    assert loop.call(lambda: 42) == 42  # the thread goes on


def test_work_that_timed_out_is_withdrawn_never_run_later(loop):
    """A caller told "the physics thread did not respond" can rely on the work not running."""
    loop.start()
    stall, ran = threading.Event(), []
    loop.call(lambda: None)  # the thread is stepping
    loop._work.put(stall.wait)  # the physics thread stalls (a hook blocked, a starved process)
    with pytest.raises(TimeoutError, match='did not respond in 0.2 s') as refused:
        loop.call(lambda: ran.append('late'), timeout=0.2)
    # and says where the thread is stuck, innermost call first (a stalled CI run left no trace)
    assert str(refused.value).split('it is at ')[1].startswith('wait (threading.py:'), refused
    stall.set()
    assert loop.call(lambda: 'after') == 'after'  # the queue behind it has run: it was not
    assert ran == []


def test_at_a_real_time_factor_the_loop_never_runs_ahead_of_the_wall_clock(loop):
    """The pacing bound only: how closely a loaded machine keeps up is bench-sim's figure."""
    loop.rtf = 1.0
    loop.start()
    t0 = time.monotonic()
    while loop.sim_time < 0.5 and time.monotonic() - t0 < 30:
        time.sleep(0.01)
    sim_seconds, wall = loop.sim_time, time.monotonic() - t0
    assert sim_seconds <= 1.05 * wall + 0.01, (sim_seconds, wall)


def test_the_automatic_publish_period_is_coarser_as_fast_as_possible():
    """0 picks 24 steps at real_time_factor 0 and 4 otherwise; a set period is kept."""
    assert publish_period_steps(0, 0.0) == 24
    assert publish_period_steps(0, 1.0) == 4
    assert publish_period_steps(0, 2.5) == 4
    assert publish_period_steps(6, 0.0) == 6
    with pytest.raises(ValueError, match='not -1'):
        publish_period_steps(-1, 1.0)


def test_a_running_loop_lowers_the_switch_interval_and_never_raises_it(loop):
    """Other threads get the GIL back within 0.1 ms of asking, not Python's 5 ms (see the loop)."""
    import sys

    from hexapod_sim.physics.physics_loop import SWITCH_INTERVAL_S

    before = sys.getswitchinterval()
    try:
        sys.setswitchinterval(0.005)
        loop.start()
        assert sys.getswitchinterval() == pytest.approx(SWITCH_INTERVAL_S, abs=2e-6)
        loop.stop()
        sys.setswitchinterval(SWITCH_INTERVAL_S / 2)
        loop.start()
        assert sys.getswitchinterval() == pytest.approx(SWITCH_INTERVAL_S / 2, abs=2e-6)
    finally:
        sys.setswitchinterval(before)
