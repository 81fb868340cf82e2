# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
sim_node's physics thread, without ROS: one gait cycle played in a loop at a real-time factor.

:class:`PhysicsLoop` steps a :class:`~hexapod_sim.simulator.Simulator` through the rows of the
cycle being played, keeps the simulation time (from the last reset), paces itself to
``rtf`` x real time (0: as fast as possible), and says when state and /clock are due (every
``period_steps`` and ``clock_steps`` steps counted from the last reset, so that the state of
"reset + N steps" is always reported). Work from other threads (a new gait, a reset, new damage)
runs between two steps (:meth:`PhysicsLoop.call`), so a trial never sees half of a change.
"""

from __future__ import annotations

from dataclasses import dataclass
import queue
import sys
import threading
import time
import traceback
from typing import Callable, TypeVar

from hexapod_sim.damage import Damage
from hexapod_sim.simulator import Simulator
from hexapod_sim.trajectory_input import CycleTable

T = TypeVar('T')


@dataclass
class LoopHooks:
    """What the loop reports; each is called from the physics thread."""

    state: Callable[[float], None]  # publish the state at this sim time [s]
    clock: Callable[[float], None]  # publish /clock
    reset: Callable[[float], None]  # the robot was reset at this sim time
    unstable: Callable[[float], None]  # the physics became unstable at this sim time
    publish_failed: Callable[[Exception], bool]  # a report raised: True = stop (shutting down)


#: State every 4 steps (60 Hz of sim time) in real time; every 24 (10 Hz) as fast as possible,
#: where sim_node runs ~18x real time and a Python reader of 60 Hz of sim time (~1,000 messages a
#: wall second) fell behind on a loaded 2-core machine until its queue dropped the samples a
#: trial reads (CI: three trials in a row repeated, then aborted).
REAL_TIME_PERIOD_STEPS = 4
FAST_PERIOD_STEPS = 24


#: The process's GIL switch interval while a loop runs [s], lowered from Python's 5 ms. The
#: physics thread holds the GIL except in short engine calls; every other thread that gives it
#: up (a syscall, an rcl call) waits a whole interval to get it back. A DART or PyBullet loop at
#: rtf 0 so made sim_node's first log line take 8-14 s and its first trajectory arrive after a
#: test's 30 s wait (CI, 2026-12-02); at 0.1 ms it takes 0.5-0.6 s, at the same physics rate.
SWITCH_INTERVAL_S = 1e-4


def publish_period_steps(requested: int, rtf: float) -> int:
    """Return the steps between state messages: ``requested``, or for 0 the default for ``rtf``."""
    if requested < 0:
        raise ValueError(
            f'publish_period_steps must be 0 (automatic) or positive, not {requested}'
        )
    if requested:
        return requested
    return FAST_PERIOD_STEPS if rtf == 0 else REAL_TIME_PERIOD_STEPS


class PhysicsLoop:
    """Play a cycle table on a simulator in a thread of its own (see the module docstring)."""

    def __init__(
        self,
        sim: Simulator,
        cycle: CycleTable,
        hooks: LoopHooks,
        rtf: float = 1.0,
        period_steps: int = 4,
        clock_steps: int = 6,
    ) -> None:
        self.sim, self.hooks = sim, hooks
        self.rtf, self.period_steps, self.clock_steps = rtf, period_steps, clock_steps
        self.cycle = cycle
        self.sim_time = 0.0
        self._work: queue.Queue[Callable[[], None]] = queue.Queue()
        self._running = False
        self._thread: threading.Thread | None = None
        self._prepare()

    # -- from any thread -------------------------------------------------------------------------
    def start(self) -> None:
        """
        Reset the robot to the cycle's first pose and start stepping.

        Lowers the process's GIL switch interval to :data:`SWITCH_INTERVAL_S` (never raises it).
        """
        sys.setswitchinterval(min(sys.getswitchinterval(), SWITCH_INTERVAL_S))
        self.reset()
        self._running = True
        self._thread = threading.Thread(target=self._run, name='physics', daemon=True)
        self._thread.start()

    def stop(self, timeout: float = 5.0) -> None:
        """Stop stepping (the simulator stays open)."""
        self._running = False
        if self._thread is not None and self._thread.is_alive():
            self._thread.join(timeout=timeout)

    def call(self, work: Callable[[], T], timeout: float = 10.0) -> T:
        """
        Run ``work`` between two physics steps; return its result (or raise its exception).

        TimeoutError: the physics thread did not take the work within ``timeout`` s; the work
        is then withdrawn, never run later (a caller told "not applied" can rely on it).
        """
        if not self._running:
            return work()  # not stepping (yet, or any more): nothing to step between
        done = threading.Event()
        box: dict[str, object] = {}
        claim = threading.Lock()  # held by whoever comes first: the physics thread or the timeout

        def wrapped() -> None:
            if not claim.acquire(blocking=False):
                return  # withdrawn: its caller gave up
            try:
                box['result'] = work()
            except Exception as exc:  # handed back to the caller
                box['error'] = exc
            finally:
                done.set()

        self._work.put(wrapped)
        if not done.wait(timeout) and claim.acquire(blocking=False):
            raise TimeoutError(
                f'the physics thread did not respond in {timeout:g} s; it is at {self.where()}'
            )
        done.wait()  # taken just as the time ran out: it finishes
        if 'error' in box:
            raise box['error']  # type: ignore[misc]
        return box.get('result')  # type: ignore[return-value]

    def where(self, frames: int = 3) -> str:
        """Say where the physics thread is now: its innermost ``frames`` calls, innermost last."""
        thread = self._thread
        frame = sys._current_frames().get(thread.ident) if thread is not None else None
        if frame is None:
            return 'no physics thread running'
        stack = traceback.extract_stack(frame)[-frames:]
        return ' < '.join(
            f'{s.name} ({s.filename.rsplit("/", 1)[-1]}:{s.lineno})' for s in reversed(stack)
        )

    # -- in the physics thread (through call) --------------------------------------------------
    def play(self, cycle: CycleTable) -> float:
        """Play ``cycle`` from its first row; return the sim time it took effect [s]."""
        self.cycle = cycle
        self._prepare()
        return self.sim_time

    def set_damage(self, damage: Damage) -> Damage:
        """Apply ``damage`` (the cycle's rows are made again for it); return what was applied."""
        applied = self.sim.set_damage(damage)
        self._prepare()
        return applied

    def reset(self) -> float:
        """Put the robot back at the origin in the cycle's first pose; return the sim time [s]."""
        self.sim.reset(self.cycle.positions[0])
        self._steps_since_reset = 0
        self._unstable_reported = False
        self._row = 0
        self._reset_stamp = self.sim_time
        self.hooks.reset(self.sim_time)
        self.hooks.state(self.sim_time)
        return self.sim_time

    def _prepare(self) -> None:
        self._rows = self.sim.prepare_rows(self.cycle.positions, self.cycle.velocities)
        self._n_rows = len(self.cycle.positions)
        self._row = 0

    def _run(self) -> None:
        wall_start, sim_start = time.monotonic(), self.sim_time
        rtf_seen = self.rtf
        while self._running:
            while True:
                try:
                    self._work.get_nowait()()
                except queue.Empty:
                    break
            sim = self.sim
            sim.apply_row(self._rows, self._row)
            if sim.step().unstable and not self._unstable_reported:
                self._unstable_reported = True  # once per reset: a bad setting repeats it
                self.hooks.unstable(self.sim_time)
            sim.update_imu()
            self._row = (self._row + 1) % self._n_rows
            self._steps_since_reset += 1
            self.sim_time = self._reset_stamp + self._steps_since_reset * sim.dt
            try:
                state = self._steps_since_reset % self.period_steps == 0
                if state or self._steps_since_reset % self.clock_steps == 0:
                    self.hooks.clock(self.sim_time)
                if state:
                    self.hooks.state(self.sim_time)
            except Exception as exc:  # a failed report must not stop the physics
                if self.hooks.publish_failed(exc):
                    return
            if self.rtf != rtf_seen:
                wall_start, sim_start, rtf_seen = time.monotonic(), self.sim_time, self.rtf
            if self.rtf > 0:
                ahead = (self.sim_time - sim_start) / self.rtf - (time.monotonic() - wall_start)
                if ahead > 0:
                    time.sleep(ahead)
