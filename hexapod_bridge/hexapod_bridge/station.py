# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The base station's side of the robot link, without ROS: what bridge_node does, as a library.

:class:`BaseStation` owns the radio port (and an Xsens on this PC, if any), the link protocol
(:class:`hexapod_bridge.link.RobotLink`), the IMU history and the trial being measured. Two
threads serve the ports; commands come from any thread and answer with typed results. What it
hears is handed to callbacks (IMU samples, the robot's attitude telemetry, a port lost or back),
and a finished trial comes back from :meth:`BaseStation.finished_trial` as a
:class:`TrialResult`: the IMU estimate of its displacement in the frame the robot started in.
bridge_node only turns those into messages.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field
import enum
import math
import threading
import time
from typing import Callable

from hexapod_bridge.link import Operation, RobotLink
from hexapod_bridge.odometry import TrialEstimate, TrialOdometry
from hexapod_bridge.protocol import legacy, xbus
from hexapod_bridge.protocol.extension import TrialState
from hexapod_bridge.serial_port import ReconnectingPort
from hexapod_description.model import load_model

#: The robot's reports that end a trial.
FINAL_STATES = (TrialState.DONE, TrialState.STOPPED, TrialState.FAILSAFE, TrialState.ESTOPPED)
#: A trial with no report this long after its walk should have ended is closed anyway [s].
OVERDUE_S = 3.0
#: The radio is heard at least this often when it works (the robot's 2 Hz telemetry, its ping
#: replies every second) [s]: a quieter link is reported (diagnostics WARN).
LINK_SILENT_S = 2.0
#: A trial during which the robot is silent this long has lost its link [s]: it ends at once.
LINK_LOST_S = 3.0
#: The IMU streams at 100 Hz (Xsens) or 2 Hz (the robot's attitude): older than this is a fault
#: (diagnostics ERROR; a trial window with such a hole ends at once) [s].
IMU_SILENT_S = 1.5
#: A trial window missing more than this many consecutive IMU samples (by the IMU's own sample
#: counter) has a gap its integration cannot bridge.
IMU_GAP_SAMPLES = 10
#: Bad frames (checksum errors and resyncs) at more than this rate [1/s] over the last
#: BAD_FRAME_WINDOW_S make the link's status WARN (a clean radio has none; 2,000 random bytes
#: make ~100 resyncs).
BAD_FRAME_RATE = 0.5
BAD_FRAME_WINDOW_S = 10.0
#: The robot pings its servos after it answers a HELLO (docs/radio-protocol.md) and reports each
#: dead one at once: this long after its VERSION every report has come [s].
SERVO_CHECK_GRACE_S = 1.0


class TrialFault(enum.IntEnum):
    """
    Why a trial's estimate cannot be scored (NONE: walked and measured whole).

    The values are hexapod_msgs/RobotTrial's constants. Those of the link and the robot's state
    (LINK_LOST, IMU_GAP, NO_END_REPORT, IMPLAUSIBLE) say nothing of the gait: the same gait may be
    walked again once the link is back. STOPPED (a stop or an emergency stop) and NO_ESTIMATE (no
    IMU, too few samples) are not the link's.
    """

    NONE = 0
    LINK_LOST = 1  # the radio port closed, the robot fell silent, or its failsafe stopped it
    IMU_GAP = 2  # IMU samples missing, or the IMU port lost, during the window
    NO_END_REPORT = 3  # the robot never reported the walk's end (it restarted, or no radio)
    STOPPED = 4  # the walk was stopped before its end (stop_trial, emergency stop)
    IMPLAUSIBLE = 5  # the estimate is not finite, or faster than the robot can walk
    NO_ESTIMATE = 6  # no IMU configured, or too few samples for an estimate


class ServoCheck(enum.IntEnum):
    """How the robot's check of every servo stands (GetServoFailures' CHECK_* constants)."""

    PENDING = 0
    DONE = 1
    UNAVAILABLE = 2


#: Faults of the link or the robot's state, not of the gait: the gait may be walked again.
RETRYABLE_FAULTS = frozenset(
    {TrialFault.LINK_LOST, TrialFault.IMU_GAP, TrialFault.NO_END_REPORT, TrialFault.IMPLAUSIBLE}
)


def _setting(default, description: str, range=None, read_only: bool = True):  # noqa: A002
    """Declare a StationConfig field with what bridge_node's parameter says of it."""
    return field(
        default=default,
        metadata={'description': description, 'range': range, 'read_only': read_only},
    )


@dataclass(frozen=True)
class StationConfig:
    """How the base station reaches the robot: bridge_node's parameters are these fields."""

    port: str = _setting('/tmp/hexapod_radio', 'Serial port of the 433 MHz radio module')
    baud: int = _setting(19200, 'Radio UART baud rate (the RF1100 modules run 19200 8N1)')
    imu_port: str = _setting('', "Serial port of an Xsens MTi wired to this PC ('' = none)")
    imu_baud: int = _setting(115200, 'Xsens baud rate')
    firmware: str = _setting('v2', "'v2' (gait-upload extension) or 'legacy' (today's firmware)")
    ping_period: float = _setting(
        1.0, 'Keep-alive period [s]; the robot stops after ~27 s without pings', range=(0.1, 2.5)
    )
    trial_duration: float = _setting(
        5.0, 'Timed walk of a trial [s] (after trial_settle)', range=(0.5, 60.0)
    )
    trial_settle: float = _setting(
        0.0,
        'Seconds a trial walks untimed before its timed trial_duration (the robot walks both); 0 ='
        " timed from standing. adapt_node's default trial: 1 s settling, 2 s timed;"
        " navigate_node's steps: 0",
        range=(0.0, 10.0),
    )
    settle_time: float = _setting(
        0.5,
        'Rest after the walk before the odometry window closes [s]; longer while the IMU says'
        ' the body still moves (at most settle_time_max)',
        range=(0.0, 10.0),
    )
    settle_time_max: float = _setting(
        1.5,
        'Longest rest after the walk before the odometry window closes [s]',
        range=(0.0, 10.0),
    )
    pre_trial_buffer: float = _setting(
        0.3, 'IMU history before a start command in the window [s]', range=(0.0, 5.0)
    )
    imu_rate: float = _setting(
        100.0, "Xsens output rate [Hz] (its sample counter's clock)", range=(1.0, 1000.0)
    )
    telemetry_period: float = _setting(
        0.5,
        'Robot attitude telemetry period requested on every (re)connect [s] '
        '(firmware default 0.5)',
        range=(0.05, 60.0),
    )
    reconnect_max_backoff: float = _setting(
        0.25, 'Longest wait between attempts to reopen a lost port [s]', range=(0.01, 5.0)
    )
    arm_on_start: bool = _setting(False, 'Arm (allow transmission) at start-up')
    leg_map: tuple[int, ...] = _setting(
        (1, 2, 3, 4, 5, 6),
        "Robot's leg number for URDF legs 1..6 (a permutation); "
        '[1, 6, 5, 4, 3, 2] if the firmware keeps its clockwise numbering (unverified)',
    )


@dataclass
class ActiveTrial:
    """The trial the station is measuring."""

    odometry: TrialOdometry
    start: float  # monotonic s when the start was sent
    crab: float  # walking direction of the gait [rad]
    duration: float  # s timed
    generation: int  # RobotLink.trial_generation once the robot acknowledged this start
    done_at: float | None = None
    settle: float = 0.0  # s walked before the timed part
    imu_start: float | None = None  # IMU clock of the newest sample when the start was sent
    fault: TrialFault = TrialFault.NONE  # the first fault seen while it was measured
    fault_reason: str = ''
    imu_arrived: float = 0.0  # monotonic s of the newest IMU sample in the window (or the start)

    def spoil(self, fault: TrialFault, reason: str) -> None:
        """Mark the trial unscorable for ``reason`` (the first fault seen is kept)."""
        if self.fault is TrialFault.NONE:
            self.fault, self.fault_reason = fault, reason

    @property
    def walk(self) -> float:
        """Seconds the robot walks: the settling and the timed part."""
        return self.settle + self.duration


@dataclass(frozen=True)
class TrialResult:
    """
    A finished trial: the robot's last word on it, the IMU estimate (if any), its validity.

    Only a trial with ``fault`` NONE was walked and measured whole: its estimate may be scored.
    An unscorable trial may still carry the estimate made of what was received (for the record).
    """

    state: str  # the robot's final trial state, or NO_REPORT
    duration: float  # s timed
    estimate: TrialEstimate | None = None
    x: float = 0.0  # displacement over the whole walk, in the frame the robot started in [m]
    y: float = 0.0
    problem: str = ''  # why it cannot be scored ('' if it can)
    yaw: float = 0.0  # heading change over the trial (the IMU's yaw) [rad]
    vx: float = 0.0  # mean velocity over the timed part, in the frame the robot started in [m/s]
    vy: float = 0.0
    walk: float = 0.0  # s walked: the settling and the timed part (0: not recorded)
    fault: TrialFault = TrialFault.NONE

    def __post_init__(self) -> None:
        if (self.fault is TrialFault.NONE) == bool(self.problem):
            raise ValueError(f'a trial result has a reason exactly when it has a fault: {self}')

    @property
    def valid(self) -> bool:
        """Whether the trial was walked and measured whole (its estimate may be scored)."""
        return self.fault is TrialFault.NONE


@dataclass(frozen=True)
class LinkSnapshot:
    """The link's health at one moment (LinkStatus)."""

    connected: bool
    armed: bool
    seconds_since_heard: float
    frames_ok: int
    checksum_errors: int
    resyncs: int
    bytes_dropped: int
    frames_sent: int
    retries: int
    last_error: str
    bad_frame_rate: float = 0.0  # checksum errors and resyncs per second, lately [1/s]
    up: bool = False  # connected, and the robot heard within LINK_LOST_S: trials can be walked


class BaseStation:
    """The robot link, the IMU and the trial in progress (see the module docstring)."""

    def __init__(
        self,
        config: StationConfig,
        on_imu: Callable[[xbus.MTData], None] = lambda m: None,
        on_attitude: Callable[[legacy.Telemetry], None] = lambda t: None,
        on_connection: Callable[[bool, str], None] = lambda up, why: None,
        log_error: Callable[[str], None] = print,
    ) -> None:
        self.config = config
        self.on_imu, self.on_attitude = on_imu, on_attitude
        self.on_connection, self.log_error = on_connection, log_error
        self.lock = threading.RLock()
        # a wrong firmware or leg map must not silently become the default: refuse to start
        self.link = RobotLink(
            baud=int(config.baud),
            ping_period=float(config.ping_period),
            firmware=str(config.firmware),
            leg_map=list(config.leg_map),
        )
        backoff = float(config.reconnect_max_backoff)
        self.radio = ReconnectingPort(str(config.port), int(config.baud), backoff)
        self.imu_port = (
            ReconnectingPort(str(config.imu_port), int(config.imu_baud), backoff)
            if config.imu_port
            else None
        )
        self.xbus = xbus.XbusParser()
        self.gait_id: int | None = None
        self.gait_crab = 0.0
        history = int(max(1, config.pre_trial_buffer * config.imu_rate)) + 1
        self.imu_history: deque = deque(maxlen=history)
        self.trial: ActiveTrial | None = None
        self._configured_connects = 0
        self._was_connected = False
        self._told_error = ''  # the last reason told for a port that is not open
        self._counter_base = 0
        self._last_counter: int | None = None
        self._bad_frames: deque[tuple[float, int]] = deque()  # (monotonic s, bad frames so far)
        self.checked_at: float | None = None  # when the robot last answered a HELLO (monotonic)
        self.max_speed = load_model().max_walking_speed  # [m/s]: no trial is faster
        if config.arm_on_start:
            self.link.arm(True, time.monotonic())
        self._running = True
        self._threads = [threading.Thread(target=self._radio_loop, name='radio', daemon=True)]
        if self.imu_port is not None:
            self._threads.append(threading.Thread(target=self._imu_loop, name='imu', daemon=True))

    def start(self) -> None:
        """Start serving the ports."""
        for thread in self._threads:
            thread.start()

    def stop(self) -> None:
        """Stop the I/O threads and close the ports."""
        self._running = False
        for thread in self._threads:
            if thread.is_alive():
                thread.join(timeout=2.0)
        self.radio.close()
        if self.imu_port is not None:
            self.imu_port.close()

    # -- commands ----------------------------------------------------------------------------
    def wait(
        self, op: Operation, timeout: float, alive: Callable[[], bool] = lambda: True
    ) -> bool:
        """Wait up to ``timeout`` s for the robot to answer ``op``; True if it did."""
        deadline = time.monotonic() + timeout
        while not op.done and time.monotonic() < deadline and self._running and alive():
            time.sleep(0.005)
        return op.done

    def arm(self, on: bool) -> None:
        """Allow transmission (or go silent)."""
        with self.lock:
            self.link.arm(on, time.monotonic())

    @property
    def armed(self) -> bool:
        """Whether the station may transmit."""
        return self.link.armed

    def upload(self, gait) -> Operation:
        """Queue a gait for the robot: it goes out once the station is armed."""
        with self.lock:
            return self.link.upload(gait)

    def abandon(self, op: Operation, reason: str) -> None:
        """Give up an upload (its frames not yet sent are dropped; it fails with ``reason``)."""
        with self.lock:
            self.link.abandon(op, reason)

    def uploaded(self, op: Operation, gait) -> None:
        """Record a confirmed upload: trials now walk ``gait``."""
        with self.lock:
            self.gait_id, self.gait_crab = op.result['gait_id'], gait.crab_angle

    def start_trial(self, alive: Callable[[], bool] = lambda: True) -> tuple[bool, str]:
        """Start a trial of the uploaded gait; return (started, what happened)."""
        with self.lock:
            if not self.link.armed:
                return False, 'not armed: call ~/arm first'
            if self.link.firmware == 'v2' and self.gait_id is None:
                return False, 'no gait uploaded yet: publish gait/parameters first'
            if self.trial is not None:
                return False, 'a trial is already running'
            odometry = TrialOdometry()
            for sample in self.imu_history:
                odometry.add(*sample)
            duration, settle = self.config.trial_duration, self.config.trial_settle
            op = self.link.start_trial(settle + duration, self.gait_id or 0)
            self.trial = ActiveTrial(
                odometry,
                time.monotonic(),
                self.gait_crab,
                duration,
                generation=self.link.trial_generation + 1,
                settle=settle,
                imu_start=odometry.newest_time(),
                imu_arrived=time.monotonic(),
            )
        if not self.wait(op, 3.0, alive) or not op.ok:
            with self.lock:
                self.trial = None
            return False, f'robot did not start the trial: {op.message or "no acknowledgement"}'
        walk = (
            f'{settle:g} s of settling, then {duration:g} s timed' if settle else f'{duration:g} s'
        )
        return True, f'trial started: gait {self.gait_id}, {walk}'

    def stop_trial(self) -> tuple[bool, str]:
        """Stop the walk."""
        with self.lock:
            op = self.link.stop_trial()
        ok = self.wait(op, 3.0) and op.ok
        return ok, op.message or 'no acknowledgement'

    def emergency_stop(self) -> None:
        """Send the emergency stop (armed or not) and disarm."""
        with self.lock:
            self.link.emergency_stop()
            self.link.arm(False, time.monotonic())

    def hello(self, timeout: float = 3.0) -> tuple[bool, str]:
        """Say HELLO and wait for the robot's VERSION (its servo health check follows)."""
        with self.lock:
            op = self.link.hello()
        ok = self.wait(op, timeout) and op.ok
        if ok:
            with self.lock:
                self.checked_at = time.monotonic()
        return ok, op.message or f'no VERSION from the robot within {timeout:g} s'

    def servo_check(self, now: float) -> tuple[ServoCheck, str]:
        """How the check of every servo stands: done (once since start), pending, unavailable."""
        if self.link.firmware == 'legacy':
            return ServoCheck.UNAVAILABLE, 'the legacy firmware has no servo check (no HELLO)'
        if self.checked_at is None:
            return ServoCheck.PENDING, 'the robot has not answered a HELLO yet'
        if now - self.checked_at < SERVO_CHECK_GRACE_S:
            return ServoCheck.PENDING, 'the robot is checking its servos'
        return ServoCheck.DONE, 'every servo checked'

    def motor_power(self, on: bool) -> Operation:
        """Servo power on or off; on also clears a latched e-stop."""
        with self.lock:
            return self.link.motor_power(on)

    # -- state -------------------------------------------------------------------------------
    def snapshot(self, now: float) -> LinkSnapshot:
        """Return the link's health now."""
        with self.lock:
            s, p = self.link.stats, self.link.parser.stats
            heard = self.link.last_heard
            bad = p.checksum_errors + p.implausible
            rate = self._bad_frame_rate(now, bad + p.resyncs)
            error = self.radio.last_error
            if rate > BAD_FRAME_RATE and self.radio.connected:
                error = (
                    f'{rate:.1f} bad frames/s over the last {BAD_FRAME_WINDOW_S:g} s (noise on the'
                    f' radio): {bad} checksum errors, {p.resyncs} resyncs,'
                    f' {p.bytes_dropped} bytes dropped so far'
                )
            return LinkSnapshot(
                connected=self.radio.connected,
                armed=self.link.armed,
                seconds_since_heard=(now - heard) if math.isfinite(heard) else math.inf,
                frames_ok=p.frames_ok,
                checksum_errors=bad,
                resyncs=p.resyncs,
                bytes_dropped=p.bytes_dropped,
                frames_sent=s.frames_sent,
                retries=s.retries,
                last_error=error,
                bad_frame_rate=rate,
                up=not self._link_problem(now),
            )

    def link_problem(self, now: float) -> str:
        """Say why the link cannot carry a trial now ('' when it can: open, the robot heard)."""
        with self.lock:
            return self._link_problem(now)

    def _link_problem(self, now: float) -> str:
        if not self.radio.connected:
            return f'the radio port is not open: {self.radio.last_error or "not yet"}'
        silent = now - self.link.last_heard
        if silent > LINK_LOST_S:
            heard = f'for {silent:.1f} s' if math.isfinite(silent) else 'since the port opened'
            return f'the robot has been silent {heard}'
        return ''

    def _bad_frame_rate(self, now: float, bad: int) -> float:
        """Bad frames per second over the last BAD_FRAME_WINDOW_S (``bad``: the count so far)."""
        history = self._bad_frames
        history.append((now, bad))
        while len(history) > 2 and now - history[1][0] >= BAD_FRAME_WINDOW_S:
            history.popleft()
        t0, b0 = history[0]
        return (bad - b0) / max(now - t0, 1.0)

    def take_events(self) -> list[tuple[str, object]]:
        """Return (and forget) what the robot reported since the last call."""
        with self.lock:
            events = list(self.link.events)
            self.link.events.clear()
        return events

    def finished_trial(self, now: float) -> TrialResult | None:
        """
        Return the trial that has just finished, once its settle time is over (else None).

        Only the robot's reports about THIS trial (its acknowledged start) can end it; a trial
        the robot never reports on ends ``OVERDUE_S`` after its walk should have. A trial whose
        link or IMU is lost ends at once, unscorable (:class:`TrialFault`).
        """
        with self.lock:
            trial = self.trial
            if trial is None:
                return None
            self._watch(trial, now)
            lost = trial.fault in (TrialFault.LINK_LOST, TrialFault.IMU_GAP)
            ours = self.link.trial_generation == trial.generation
            finished = ours and self.link.trial_state in FINAL_STATES
            overdue = now - trial.start > trial.walk + OVERDUE_S
            if trial.done_at is None and (finished or overdue or lost):
                trial.done_at = now
            if trial.done_at is None:
                return None
            since, rest = now - trial.done_at, self.config.settle_time
            if lost:  # nothing to settle: the window cannot be used
                closes = True
            elif self.imu_port is None:  # nothing to wait for
                closes = since >= rest
            else:
                closes = trial.odometry.window_closes(since, rest, self.config.settle_time_max)
            if not closes:
                return None
            self.trial = None
            state = self.link.trial_state.name if ours else 'NO_REPORT'
            self._judge_end(trial, state)
        return self._result(trial, state)

    def _watch(self, trial: ActiveTrial, now: float) -> None:
        """Spoil a trial in flight whose robot or IMU has fallen silent (call with the lock)."""
        if trial.done_at is not None:
            return
        silent = now - self.link.last_heard
        if silent > LINK_LOST_S and now - trial.start > LINK_LOST_S:
            trial.spoil(TrialFault.LINK_LOST, f'the robot was silent for {silent:.1f} s')
        if self.imu_port is not None and now - trial.imu_arrived > IMU_SILENT_S:
            trial.spoil(TrialFault.IMU_GAP, f'no IMU sample for {now - trial.imu_arrived:.1f} s')

    def _judge_end(self, trial: ActiveTrial, state: str) -> None:
        """Spoil a trial the robot did not walk to its end, by its last report."""
        if self.link.firmware == 'legacy':  # it reports nothing on trials: its walk is its own
            return
        if state == 'NO_REPORT':
            trial.spoil(
                TrialFault.NO_END_REPORT,
                "the robot never reported the walk's end (it restarted, or the radio lost it)",
            )
        elif state == TrialState.FAILSAFE.name:
            trial.spoil(
                TrialFault.LINK_LOST, "the robot's failsafe stopped the walk: it lost the pings"
            )
        elif state != TrialState.DONE.name:
            trial.spoil(TrialFault.STOPPED, f'the walk was stopped before its end ({state})')

    def _result(self, trial: ActiveTrial, state: str) -> TrialResult:
        """Return a closed trial's result: its estimate and whether it may be scored."""

        def unscorable(fault: TrialFault, problem: str, **kw) -> TrialResult:
            trial.spoil(fault, problem)
            return TrialResult(
                state, trial.duration, problem=trial.fault_reason, fault=trial.fault, **kw
            )

        if self.imu_port is None:
            return unscorable(TrialFault.NO_ESTIMATE, 'no IMU configured')
        timed = trial.odometry.timed_part(trial.imu_start, trial.settle, trial.duration)
        try:
            est = trial.odometry.estimate(trial.crab, trial.duration, timed)
        except ValueError as exc:
            return unscorable(TrialFault.NO_ESTIMATE, f'no odometry: {exc}')
        if not (math.isfinite(est.speed) and math.isfinite(est.distance)):
            return unscorable(
                TrialFault.IMPLAUSIBLE, f'the IMU estimate is not finite (speed {est.speed!r} m/s)'
            )
        x, y = trial.odometry.in_start_frame(est.displacement)
        vx, vy = (v / trial.duration for v in trial.odometry.in_start_frame(est.timed))
        if math.hypot(vx, vy) > self.max_speed:
            trial.spoil(
                TrialFault.IMPLAUSIBLE,
                f'the IMU estimate, {math.hypot(vx, vy):.2f} m/s, is faster than the robot can'
                f' walk ({self.max_speed:.2f} m/s)',
            )
        return TrialResult(
            state,
            trial.duration,
            est,
            x,
            y,
            problem=trial.fault_reason,
            yaw=est.yaw_change,
            vx=vx,
            vy=vy,
            walk=trial.walk,
            fault=trial.fault,
        )

    # -- I/O threads -----------------------------------------------------------------------
    def _guarded(self, body, name: str) -> None:
        """
        Run a thread's loop body until stopped.

        An unexpected error is logged (once per kind) and the loop goes on.
        """
        seen: set[type] = set()
        while self._running:
            try:
                body()
            except Exception as exc:  # keep the link alive whatever one iteration hit
                if not self._running:
                    return
                if type(exc) not in seen:
                    seen.add(type(exc))
                    self.log_error(f'{name} thread: {exc!r} (continuing)')
                time.sleep(0.01)

    def _radio_loop(self) -> None:
        self._guarded(self._radio_once, 'radio')

    def _imu_loop(self) -> None:
        self._guarded(self._imu_once, 'imu')

    def _radio_once(self) -> None:
        """One turn of the radio thread: (re)open, read, hand bytes to the link, write."""
        now = time.monotonic()
        self._report_connection_change()
        if not self.radio.ensure_open(now):
            self._spoil(TrialFault.LINK_LOST, f'the radio port was lost: {self.radio.last_error}')
            time.sleep(0.02)
            return
        self._report_connection_change()
        data = self.radio.read(0.005)
        now = time.monotonic()
        with self.lock:
            if self.radio.connects != self._configured_connects:
                if self._configured_connects:
                    self._spoil_locked(TrialFault.LINK_LOST, 'the radio port was reopened')
                self._configured_connects = self.radio.connects
                self.link.set_telemetry_period(float(self.config.telemetry_period))
            frames = self.link.receive(data, now) if data else []
            out = self.link.poll(now)
        for frame in out:
            if not self.radio.write(frame):
                break
        for frame in frames:
            if isinstance(frame, legacy.Telemetry) and self.imu_port is None:
                self.on_attitude(frame)

    def _report_connection_change(self) -> None:
        """
        Tell at once (not at the next status tick) when the port goes or comes.

        A port that cannot be opened is told too, once per reason (a port that does not exist
        at start-up never "goes", and its reason would otherwise only be in the link status).
        """
        connected = self.radio.connected
        why = self.radio.last_error
        if connected != self._was_connected or (not connected and why and why != self._told_error):
            self._was_connected = connected
            self._told_error = '' if connected else why
            self.on_connection(connected, why)

    def _spoil(self, fault: TrialFault, reason: str) -> None:
        """Spoil the trial in flight, if any, for ``reason``."""
        with self.lock:
            self._spoil_locked(fault, reason)

    def _spoil_locked(self, fault: TrialFault, reason: str) -> None:
        trial = self.trial
        if trial is not None and trial.done_at is None:
            trial.spoil(fault, reason)

    def _imu_once(self) -> None:
        now = time.monotonic()
        if not self.imu_port.ensure_open(now):
            self._spoil(TrialFault.IMU_GAP, f'the IMU port was lost: {self.imu_port.last_error}')
            time.sleep(0.02)
            return
        if self.imu_port.connects and self._last_counter is None:
            self.imu_port.write(xbus.GO_TO_MEASUREMENT)
        data = self.imu_port.read(0.01)
        for message in self.xbus.feed(data) if data else []:
            if isinstance(message, xbus.MTData):
                self.add_imu(message)

    def add_imu(self, m: xbus.MTData) -> None:
        """Take one Xsens sample: the IMU history, the trial's window, then ``on_imu``."""
        # unwrap the uint16 sample counter into a monotonic IMU clock
        if self._last_counter is not None and m.counter < self._last_counter:
            self._counter_base += 0x10000
        self._last_counter = m.counter
        sample = ((self._counter_base + m.counter) / self.config.imu_rate, m.acc, m.euler)
        with self.lock:
            history, gap = self.imu_history, IMU_GAP_SAMPLES / self.config.imu_rate
            if history and sample[0] - history[-1][0] > gap:
                history.clear()  # a window never starts with samples from before a gap
            history.append(sample)
            trial = self.trial
            if trial is not None:
                newest = trial.odometry.newest_time()
                if newest is not None and sample[0] - newest > gap:
                    trial.spoil(
                        TrialFault.IMU_GAP,
                        f"the IMU's sample counter jumped by"
                        f' {round((sample[0] - newest) * self.config.imu_rate)} (samples lost, or'
                        ' the IMU restarted)',
                    )
                trial.imu_arrived = time.monotonic()
                trial.odometry.add(*sample)
        self.on_imu(m)
