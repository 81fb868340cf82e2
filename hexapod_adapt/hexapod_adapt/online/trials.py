# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Trials through a ROS graph, without ROS: the sim, robot and manual trial procedures.

A trial function (``trial(niche) -> outcome``, what an adaptation session's driver calls) is
built from a :class:`SimPort` or a :class:`RobotPort` (the few things a trial does to the graph,
implemented over rclpy by :mod:`hexapod_adapt.ros.graph_port`), the odometry received so far
(:class:`OdomLog`) and a :class:`Waiter`. Speeds are measured along the gait's walking direction
(its crab angle):

``sim``     publish the gait, wait until sim_node plays it (it echoes the gait's stamp), reset,
            then time the odometry from reset + settle to reset + settle + duration of sim time;
``robot``   upload through bridge_node (its typed answer confirms it), stand still, start the
            trial, take the trial's odometry message (the bridge's IMU estimate);
``manual``  upload, then wait for the operator's tape-measured distance.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field
import math
import threading
import time
from typing import Callable, ClassVar, Generic, Protocol, TypeVar

from hexapod_adapt.online.adaptation import (
    TrialAborted,
    TrialCancelled,
    TrialOutcome,
    WaitTimedOut,
)
from hexapod_adapt.online.diagnosis import TrialRecord
from hexapod_gait import GaitParameters
import numpy as np

MODES = ('sim', 'robot', 'manual')
T = TypeVar('T')

#: A reported trial distance beyond this is a typo, not a walk [m].
MAX_REPORTED_DISTANCE = 50.0


@dataclass(frozen=True)
class OdomSample:
    """One odometry message as a trial reads it."""

    stamp_ns: int  # header stamp
    x: float  # position in the odom frame [m]
    y: float
    vx: float  # twist (the bridge's trial-mean velocity) [m/s]
    vy: float
    received: float  # time.monotonic() when it arrived
    upside_down: bool = False  # the body's up axis below the horizontal (a fall)
    tilt: float = 0.0  # the body's larger of |roll| and |pitch| [rad]
    attitude: tuple[float, float, float] = (0.0, 0.0, 0.0)  # roll, pitch, yaw [rad]


def odometry_record(
    samples: list[OdomSample], t0_ns: int, end_ns: int, crab: float, period: float
) -> TrialRecord | None:
    """
    Return a trial's record from its odometry: the samples stamped in (``t0_ns``, ``end_ns``].

    Timed from ``t0_ns``, the gait's start (phase 0). None when fewer than two samples are
    there (a trial the tip guard stopped at once) or they cannot make a record.
    """
    window = sorted((s for s in samples if t0_ns < s.stamp_ns <= end_ns), key=lambda s: s.stamp_ns)
    unique = [s for i, s in enumerate(window) if i == 0 or s.stamp_ns != window[i - 1].stamp_ns]
    if len(unique) < 2:
        return None
    t = np.array([(s.stamp_ns - t0_ns) * 1e-9 for s in unique])
    position = np.array([(s.x, s.y) for s in unique])
    attitude = np.array([s.attitude for s in unique])
    try:
        return TrialRecord(t, position, attitude, crab, period)
    except ValueError:
        return None  # not a trial's samples (a stamp twice, a value not finite): no record


class SampleLog(Generic[T]):
    """The latest ``maxlen`` messages of a topic, shared between threads."""

    def __init__(self, maxlen: int = 20000) -> None:
        self._samples: deque[T] = deque(maxlen=maxlen)
        self._lock = threading.Lock()

    def append(self, sample: T) -> None:
        """Add one message."""
        with self._lock:
            self._samples.append(sample)

    def snapshot(self) -> list[T]:
        """Return every message kept, oldest first."""
        with self._lock:
            return list(self._samples)

    def latest(self) -> T | None:
        """Return the newest message, if any."""
        with self._lock:
            return self._samples[-1] if self._samples else None

    def received_after(self, t: float) -> T | None:
        """Return the first message received after monotonic time ``t`` (its ``received``)."""
        with self._lock:
            return next((s for s in self._samples if s.received > t), None)


class OdomLog(SampleLog[OdomSample]):
    """The odometry received so far."""

    def peak_tilt_after(self, stamp_ns: int) -> float:
        """
        Return the largest tilt [rad] of the samples stamped after ``stamp_ns`` (0 if none).

        Strictly after: sim_node may publish two samples stamped with a reset's time, the
        scheduled one from before the reset (a robot still on its back after a tipped trial)
        and then the pose at the origin, which has no tilt to miss.
        """
        peak = 0.0
        with self._lock:
            for s in reversed(self._samples):  # newest first: a trial's samples are the last
                if s.stamp_ns <= stamp_ns:
                    break
                peak = max(peak, s.tilt)
        return peak


@dataclass(frozen=True)
class TiltSample:
    """One attitude reading (the IMU's) as a trial's tip guard reads it."""

    tilt: float  # the larger of |roll| and |pitch| [rad]
    received: float  # time.monotonic() when it arrived
    attitude: tuple[float, float, float] = (0.0, 0.0, 0.0)  # roll, pitch, yaw [rad]
    stamp_ns: int = 0  # header stamp (when bridge_node read it; 0: none)


class TiltLog(SampleLog[TiltSample]):
    """The robot's attitude readings received so far (bridge_node's imu/data)."""

    def peak_since(self, t: float) -> float:
        """Return the largest tilt [rad] received after monotonic time ``t`` (0 if none)."""
        peak = 0.0
        with self._lock:
            for s in reversed(self._samples):
                if s.received <= t:
                    break
                peak = max(peak, s.tilt)
        return peak

    def between(self, t0: float, t1: float) -> list[TiltSample]:
        """Return the readings received after monotonic time ``t0`` and by ``t1``, in order."""
        with self._lock:
            return [s for s in self._samples if t0 < s.received <= t1]

    def tilt_at(self, t: float) -> float | None:
        """Return the newest tilt [rad] received at or before monotonic time ``t`` (None: none)."""
        with self._lock:
            for s in reversed(self._samples):
                if s.received <= t:
                    return s.tilt
        return None


def reading_times(samples: list[TiltSample]) -> np.ndarray:
    """
    Return when each reading was taken, on the receiving clock (monotonic) [s].

    Receipt times carry the graph's delivery jitter (DDS, the executor). Where every reading is
    stamped and the stamps rise, a reading's time is its stamp moved onto the receiving clock by
    the smallest receipt-minus-stamp offset among them (the reading delivered fastest): the
    stamps' spacing, the receipt clock's origin, on any machine whose clock runs at the same
    rate. Otherwise the receipt times.
    """
    received = np.array([s.received for s in samples], dtype=float)
    stamps = np.array([s.stamp_ns for s in samples], dtype=np.int64)
    if len(samples) < 2 or np.any(stamps <= 0) or np.any(np.diff(stamps) <= 0):
        return received
    relative = (stamps - stamps[0]) * 1e-9  # (float seconds lose ns of a wall-clock stamp)
    return relative + np.min(received - relative)


def imu_record(
    samples: list[TiltSample],
    started: float,
    velocity: tuple[float, float],
    crab: float,
    period: float,
) -> TrialRecord | None:
    """
    Return a robot trial's record from the IMU's attitude and the bridge's mean velocity.

    Timed from ``started`` (the trial's start, monotonic; the gait's phase 0 within the link's
    latency), each reading at its stamp where the readings are stamped (:func:`reading_times`).
    The robot reports no path, only the trial's mean ``velocity`` in the frame it
    started in: the position moves along it at that speed, and yaw is taken from the first
    reading (the start frame). None when fewer than two readings came.
    """
    if len(samples) < 2:
        return None
    t = reading_times(samples) - started
    attitude = np.array([s.attitude for s in samples])
    attitude[:, 2] = np.unwrap(attitude[:, 2]) - attitude[0, 2]
    position = np.outer(t, velocity)
    try:
        return TrialRecord(t, position, attitude, crab, period)
    except ValueError:
        return None  # readings that cannot make a record (a time twice): no record


@dataclass(frozen=True)
class TrialLogs:
    """What a run's trials read from the graph, as it arrives."""

    odom: OdomLog  # sim_node's odometry (sim trials)
    results: 'SampleLog[RobotTrialResult]'  # bridge_node's trial results (robot, manual trials)
    tilts: TiltLog  # the robot's IMU attitude (robot trials' tip guard)


class Waiter:
    """
    Polls a condition until it holds, or raises :class:`TrialAborted` saying what did not come.

    ``alive()`` false (the node shuts down) stops the wait; ``cancelled()`` true (the goal's
    cancel) stops it with :class:`TrialCancelled` within a poll; ``check()`` (every
    ``check_period`` s) returns a reason to stop ('' to go on), e.g. a node name taken twice.
    """

    def __init__(
        self,
        alive: Callable[[], bool],
        check: Callable[[], str] | None = None,
        check_period: float = 1.0,
        poll: float = 0.005,
        clock: Callable[[], float] = time.monotonic,
        sleep: Callable[[float], None] = time.sleep,
        cancelled: Callable[[], bool] | None = None,
    ) -> None:
        self.alive, self.check, self.check_period = alive, check, check_period
        self.poll, self.clock, self.sleep = poll, clock, sleep
        self.cancelled = cancelled

    def until(self, predicate: Callable[[], object], timeout: float, what: str):
        """Return ``predicate()``'s first truthy value within ``timeout`` s."""
        began = now = self.clock()
        deadline, next_check = now + timeout, now + self.check_period
        while (now := self.clock()) < deadline:
            if not self.alive():
                raise TrialAborted('shutting down')
            if self.cancelled is not None and self.cancelled():
                raise TrialCancelled(f'cancelled while waiting for {what}')
            value = predicate()
            if value:
                return value
            if self.check is not None and now >= next_check:
                next_check = now + self.check_period
                reason = self.check()
                if reason:
                    raise TrialAborted(reason)
            self.sleep(self.poll)
        raise WaitTimedOut(f'timed out after {self.clock() - began:.3g} s waiting for {what}')


def along(dx: float, dy: float, crab: float) -> float:
    """Component of (dx, dy) along the walking direction ``crab`` [rad]."""
    return dx * math.cos(crab) + dy * math.sin(crab)


def sim_trial_speed(
    samples: list[OdomSample], t0_ns: int, duration: float, crab: float, settle: float = 0.0
) -> float | None:
    """
    Speed [m/s] from the odometry stamped at reset + ``settle`` and ``duration`` s later.

    The gait walks ``settle`` s untimed first (0: timed from standing, the thesis's trial). None
    if either sample was lost in transport (the trial must be repeated). A robot that ends the
    trial upside down fell over: 0, as the library's evaluation scores a fall.
    """
    begin = t0_ns + int(round(settle * 1e9))
    end = begin + int(round(duration * 1e9))
    start = [s for s in samples if abs(s.stamp_ns - begin) < 1000]
    finish = [s for s in samples if abs(s.stamp_ns - end) < 1000]
    if not (start and finish):
        return None
    if finish[-1].upside_down:
        return 0.0
    return along(finish[-1].x - start[-1].x, finish[-1].y - start[-1].y, crab) / duration


@dataclass(frozen=True)
class Upload:
    """bridge_node's answer to an upload."""

    ok: bool
    message: str
    archive_index: int
    answered: bool = True  # the robot answered (False: no answer came, the link's fault)


class SimPort(Protocol):
    """What a sim trial does to the graph: gait_node and sim_node."""

    def publish_gait(self, gait: GaitParameters) -> tuple[int, float]:
        """Publish ``gait`` on gait/parameters: (its unique stamp [ns], its crab angle [rad])."""

    def active_stamp(self) -> int | None:
        """Stamp of the gait sim_node plays (sim/active_trajectory)."""

    def reset_stamp(self) -> int | None:
        """Stamp of sim_node's latest reset (sim/last_reset)."""

    def reset(self) -> tuple[bool, str]:
        """Call sim_node's reset; TrialAborted if it does not answer."""

    def stand(self) -> None:
        """Publish the standing gait on gait/parameters (the simulated robot stops walking)."""


class RobotPort(Protocol):
    """What a robot or manual trial does to the graph: bridge_node."""

    def upload(self, gait: GaitParameters, timeout: float) -> tuple[Upload, float]:
        """Upload ``gait`` through bridge_node: (its answer, its crab angle [rad])."""

    def start_trial(self) -> tuple[bool, str]:
        """Call bridge_node's start_trial; TrialAborted if it does not answer."""

    def stop_trial(self) -> tuple[bool, str]:
        """Stop the robot's trial through bridge_node (it stands); TrialAborted if no answer."""

    def stand(self) -> None:
        """Make the robot stand: its trial is over."""

    def link_problem(self) -> str:
        """Say why bridge_node's radio link cannot carry a trial now ('' when it can)."""

    def link_heard(self) -> float:
        """Say when bridge_node's newest link status came (time.monotonic(); -inf: none yet)."""


class TrialPort(SimPort, RobotPort, Protocol):
    """A port for every mode (:class:`hexapod_adapt.ros.graph_port.GraphPort` is one)."""


@dataclass(frozen=True)
class TrialTiming:
    """How long trials last and wait."""

    duration: float  # s of walking measured
    timeout: float  # wall-clock limit of one wait [s]
    stand_still: float = 1.0  # robot modes: rest before the start (clean IMU window) [s]
    settle: float = 0.0  # s walked untimed before the timed ``duration``

    @property
    def walking(self) -> float:
        """Seconds a trial walks: the settling and the timed part [s]."""
        return self.settle + self.duration


@dataclass
class SimTrials:
    """Mode ``sim``: trials through gait_node + sim_node on sim time."""

    ATTEMPTS: ClassVar[int] = 3

    gaits: GaitOf
    port: SimPort
    odom: OdomLog
    waiter: Waiter
    timing: TrialTiming
    warn: Callable[[str], None]
    #: [rad] a trial whose body (the odometry's attitude) tilts past this is stopped: the robot
    #: stands, and the trial is a tipped, failed one (pi: no guard)
    tip_guard: float = math.pi

    def __call__(self, niche: int) -> TrialOutcome:
        """Measure the speed of the gait of ``niche`` [m/s], or stop it when it tips."""
        duration, timeout, wait = self.timing.duration, self.timing.timeout, self.waiter.until
        for attempt in range(self.ATTEMPTS):
            stamp, crab = self.port.publish_gait(self.gaits(niche))
            wait(
                lambda: self.port.active_stamp() == stamp,
                timeout,
                'sim_node to play the gait (are gait_node and sim_node running?)',
            )
            before = self.port.reset_stamp() or -1
            ok, message = self.port.reset()
            if not ok:
                raise TrialAborted(f'sim_node refused the reset: {message}')
            t0 = wait(
                lambda: r if (r := self.port.reset_stamp() or -1) > before else None,
                timeout,
                'the reset to take effect',
            )
            end = t0 + int(round(self.timing.walking * 1e9))
            wait(
                lambda: (
                    (s := self.odom.latest()) is not None
                    and (s.stamp_ns >= end or self.odom.peak_tilt_after(t0) > self.tip_guard)
                ),
                timeout,
                f'{self.timing.walking:g} s of simulated odometry',
            )
            peak = self.odom.peak_tilt_after(t0)
            if peak > self.tip_guard:
                self.port.stand()
                return TrialOutcome(0.0, True, peak)
            samples = self.odom.snapshot()
            speed = sim_trial_speed(samples, t0, duration, crab, self.timing.settle)
            if speed is not None:
                period = self.gaits(niche).period
                record = odometry_record(samples, t0, end, crab, period)
                return TrialOutcome(speed, False, peak, record)
            self.warn(
                f'odometry sample lost in transport; repeating the trial (attempt {attempt + 2})'
            )
        raise TrialAborted(
            "odometry samples kept getting lost (is sim_node's publish_period_steps a divisor "
            'of the trial length and of the settling time in steps? Or too small for this '
            'machine to keep up with at real_time_factor 0, where 0, automatic, gives 24?)'
        )


class LinkFault(Exception):
    """
    A trial not walked or not measured whole, for a reason of the link or the robot's state.

    Never scored: the same gait is walked again once the link is back (:class:`RobotTrials`).
    ``walked``: the robot started the walk (False: the upload or the start went unanswered).
    """

    def __init__(self, reason: str, walked: bool = True) -> None:
        super().__init__(reason)
        self.walked = walked


#: The gait of an archive niche, its ``archive_index`` set (what a trial procedure sends).
GaitOf = Callable[[int], GaitParameters]


def _uploaded(port: RobotPort, gait: GaitParameters, timeout: float) -> float:
    """Upload ``gait``; return its crab angle, or raise with the robot's reason."""
    niche = gait.archive_index
    answer, crab = port.upload(gait, timeout)
    if not answer.ok and not answer.answered:
        raise LinkFault(f'the robot did not answer the upload: {answer.message}', walked=False)
    if not answer.ok:
        raise TrialAborted(answer.message or 'the robot did not confirm the upload')
    if answer.archive_index != niche:
        raise TrialAborted(
            f'the robot did not confirm the upload of archive gait {niche} (it confirmed '
            f'{answer.archive_index})'
        )
    return crab


#: How long a robot trial waits for a fallen robot to be put back on its feet [s].
RIGHTING_TIMEOUT = 300.0
#: How long a robot run waits for a lost radio link to come back before it ends [s].
LINK_RETURN_TIMEOUT = 60.0
#: How long a robot run waits after a fault for a link status newer than it [s]: bridge_node
#: sends one at its ``status_rate`` (5 Hz by default) and at once when the radio port changes.
LINK_STATUS_WAIT = 2.5
#: Walks of one gait a robot run makes while faults spoil them, before it ends.
ROBOT_ATTEMPTS = 3


@dataclass(frozen=True)
class RobotTrialResult:
    """One of bridge_node's trial results (``trial_result``) as a robot trial reads it."""

    valid: bool  # walked and measured whole: may be scored
    retryable: bool  # spoilt by the link or the robot's state, not the gait
    reason: str  # why it cannot be scored ('' when valid)
    vx: float  # mean velocity over the timed part, in the frame the robot started in [m/s]
    vy: float
    received: float  # time.monotonic() when it arrived


@dataclass
class RobotTrials:
    """
    Mode ``robot``: trials through bridge_node, measured by its IMU odometry.

    Only a trial the bridge says was walked and measured whole is scored, and only at a speed the
    robot can walk (``max_speed``). One spoilt by the link or the robot's state (the link lost,
    the robot restarted, an IMU gap, no answer to the upload or the start) is said through
    ``warn`` and walked again once ``link()`` says the link is back (up to ``link_timeout`` s),
    ``attempts`` walks at most; else the run ends with the reason.
    """

    gaits: GaitOf
    port: RobotPort
    results: SampleLog[RobotTrialResult]
    waiter: Waiter
    timing: TrialTiming
    #: why the radio link cannot carry a trial now ('' when it can): bridge_node's link status
    link: Callable[[], str]
    warn: Callable[[str], None]
    max_speed: float
    sleep: Callable[[float], None] = time.sleep
    clock: Callable[[], float] = time.monotonic
    #: the IMU's attitude (bridge_node's imu/data) and the guard [rad]: a trial that tilts the
    #: body past it is stopped through bridge_node's stop_trial (pi: no guard)
    tilts: TiltLog | None = None
    tip_guard: float = math.pi
    #: a robot lying past the guard (a trial tipped it) is not started: the operator is asked to
    #: put it back on its feet, and the trial waits for that this long [s]
    righting_timeout: float = RIGHTING_TIMEOUT
    link_timeout: float = LINK_RETURN_TIMEOUT
    attempts: int = ROBOT_ATTEMPTS
    #: when the newest link status behind ``link()`` came (``clock()`` time; inf: ``link()`` is
    #: always current). A fault is judged only on a status that came after it: the one before
    #: may still say the link is up (a result can be read before the status sent ahead of it)
    link_heard: Callable[[], float] = lambda: math.inf

    def __call__(self, niche: int) -> TrialOutcome:
        """Measure the speed of the gait of ``niche`` [m/s], or stop it when it tips."""
        spoilt = unanswered = 0  # walks spoilt; uploads or starts the robot did not answer
        while True:
            try:
                return self._walk(niche)
            except LinkFault as fault:
                faulted = self.clock()
                spoilt += fault.walked
                unanswered += not fault.walked
                if max(spoilt, unanswered) >= self.attempts:
                    raise TrialAborted(
                        f'gait {niche} was not walked and measured whole ({spoilt} walks spoilt,'
                        f' {unanswered} unanswered); the last: {fault}'
                    ) from None
                self.warn(
                    f'trial of gait {niche} not scored: {fault}; it is walked again once the'
                    f' radio link works (try {spoilt + unanswered + 1}; the run ends after'
                    f' {self.attempts} spoilt walks of one gait)'
                )
                self._wait_link(faulted)
                self._stand()

    def _walk(self, niche: int) -> TrialOutcome:
        crab = _uploaded(self.port, self.gaits(niche), self.timing.timeout)
        self._wait_upright()
        self.sleep(max(0.0, self.timing.stand_still))
        ok, message = self.port.start_trial()
        if not ok:
            problem = self.link()
            if problem:
                raise LinkFault(
                    f'the robot did not start the trial: {message} ({problem})', walked=False
                )
            raise TrialAborted(f'bridge_node did not start the trial: {message}')
        started = self.clock()
        tilts = self.tilts

        def peak() -> float:
            return tilts.peak_since(started) if tilts is not None else float('nan')

        try:
            result = self.waiter.until(
                lambda: (
                    self.results.received_after(started) or (peak() > self.tip_guard and 'tipped')
                ),
                self.timing.walking + self.timing.timeout,
                "the trial's result from bridge_node (trial_result)",
            )
        except TrialCancelled:
            self._stand()  # a cancelled run leaves the robot standing, not walking
            raise
        if result == 'tipped':
            self.port.stop_trial()
            return TrialOutcome(0.0, True, peak())
        if not result.valid:
            if result.retryable:
                raise LinkFault(result.reason)
            raise TrialAborted(f'the trial cannot be scored: {result.reason}')
        speed = along(result.vx, result.vy, crab)
        if not math.isfinite(speed) or math.hypot(result.vx, result.vy) > self.max_speed:
            raise LinkFault(
                f'the measured {math.hypot(result.vx, result.vy):.2f} m/s is faster than the robot'
                f' can walk ({self.max_speed:.2f} m/s)'
            )
        record = None
        if tilts is not None:
            walked = tilts.between(started, started + self.timing.walking)
            period = self.gaits(niche).period
            record = imu_record(walked, started, (result.vx, result.vy), crab, period)
        return TrialOutcome(speed, False, peak(), record)

    def _stand(self) -> None:
        """Stop a walk the robot may still make (it heard no stop while the link was down)."""
        try:
            self.port.stop_trial()
        except TrialAborted:
            pass  # a robot that does not answer is walked again all the same: the upload says

    def _wait_link(self, faulted: float) -> None:
        """Wait until the link can carry a trial (at once if it can), or end the run."""
        try:  # a status newer than the fault (the next tick, or at once on a port change)
            self.waiter.until(
                lambda: self.link_heard() > faulted, LINK_STATUS_WAIT, 'a newer link status'
            )
        except WaitTimedOut:
            pass  # none came: link() says the status is stale
        if not self.link():
            return
        self.warn(f'radio link down ({self.link()}): waiting up to {self.link_timeout:g} s for it')
        began = self.clock()
        try:
            self.waiter.until(lambda: not self.link(), self.link_timeout, 'the radio link')
        except WaitTimedOut as exc:
            raise TrialAborted(
                f'the radio link did not come back in {self.clock() - began:.0f} s: {self.link()}'
            ) from exc
        self.warn(f'radio link back after {self.clock() - began:.1f} s')

    def _wait_upright(self) -> None:
        """Wait until the IMU says the body is within the guard (no reading yet: go on)."""
        tilts = self.tilts
        if tilts is None or self.tip_guard >= math.pi:
            return

        def upright() -> bool:
            tilt = tilts.tilt_at(self.clock())
            return tilt is None or tilt <= self.tip_guard

        if upright():
            return
        self.warn(
            f'the robot lies tilted {math.degrees(tilts.tilt_at(self.clock()) or 0.0):.0f}'
            f' deg, past the {math.degrees(self.tip_guard):.0f} deg tip guard: put it back on'
            f' its feet; the next trial waits for it (up to {self.righting_timeout:.0f} s)'
        )
        self.waiter.until(upright, self.righting_timeout, 'the robot back on its feet')


def reported_distance_problem(distance: float) -> str:
    """Why an operator's reported distance [m] cannot be a trial's ('' if it can)."""
    if not math.isfinite(distance) or abs(distance) > MAX_REPORTED_DISTANCE:
        return f'distance {distance!r} m is not a plausible trial distance'
    return ''


#: How long a manual trial waits for the operator's distance [s].
MANUAL_REPORT_TIMEOUT = 600.0


@dataclass
class ManualTrials:
    """
    Mode ``manual``: the robot walks the uploaded gait; the operator reports the distance.

    The gait is uploaded and the walk started through bridge_node (its ``~/start_trial``: the
    trial's settling and timed part, as a robot trial); once bridge_node says the walk ended
    (``trial_result``, whatever its IMU measured) the operator is asked for the distance walked
    along the walking direction (``report_distance``); only then is a distance taken.
    """

    gaits: GaitOf
    port: RobotPort
    results: SampleLog[RobotTrialResult]
    waiter: Waiter
    timing: TrialTiming
    prompt: Callable[[str], None]
    sleep: Callable[[float], None] = time.sleep
    clock: Callable[[], float] = time.monotonic
    report_timeout: float = MANUAL_REPORT_TIMEOUT
    waiting: bool = False
    _reported: list[float] = field(default_factory=list)

    def report(self, distance: float) -> str:
        """Take the operator's distance [m]; return why it was refused ('' if taken)."""
        problem = reported_distance_problem(distance)
        if problem:
            return problem
        if not self.waiting:
            return 'no manual trial is waiting for a distance (the walk has not ended yet)'
        self._reported.append(float(distance))
        return ''

    def __call__(self, niche: int) -> float:
        """Measure the speed of the gait of ``niche`` [m/s] from the operator's distance."""
        try:
            _uploaded(self.port, self.gaits(niche), self.timing.timeout)
        except LinkFault as fault:
            raise TrialAborted(str(fault)) from None
        self.sleep(max(0.0, self.timing.stand_still))
        ok, message = self.port.start_trial()
        if not ok:
            raise TrialAborted(f'bridge_node did not start the walk: {message}')
        started = self.clock()
        self.waiter.until(
            lambda: self.results.received_after(started),
            self.timing.walking + self.timing.timeout,
            "the walk's end from bridge_node (trial_result)",
        )
        self._reported.clear()
        self.waiting = True
        self.prompt(
            f'trial with archive gait {niche} walked {self.timing.walking:g} s: measure the'
            ' distance along its walking direction and report it: report_distance METRES'
        )
        try:
            reported = self.waiter.until(
                lambda: list(self._reported),  # a list: a report of 0.0 m is an answer too
                self.report_timeout,
                "the operator's distance (report_distance)",
            )
        finally:
            self.waiting = False
        return reported[-1] / self.timing.walking  # the tape measures the whole walk
