# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Host side of the radio link, without I/O.

What to transmit when, and what received frames mean. bridge_node owns the serial port and threads
and calls :meth:`RobotLink.receive` with bytes read and :meth:`RobotLink.poll` to get bytes to
write.

Transmission rules:
  * nothing is sent unless armed, except an emergency stop (always sent, three times);
  * the radio carries ~baud/10 bytes/s: a token bucket paces frames so the link is never
    over-driven, and frames are chosen by priority: emergency stop > keep-alive ping >
    trial start/stop > movement > gait upload;
  * a ping goes out every ``ping_period`` s while armed, so however busy the link is the
    robot's failsafe (about 11 missed 2.5 s check windows) never trips;
  * extension commands are acknowledged by sequence number and re-sent after
    ``ack_timeout`` up to ``max_retries`` times; an upload is a window of SET_PARAM frames and
    a COMMIT, complete when the COMMIT is acknowledged OK.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field, replace
import itertools
import math
from typing import Any

from hexapod_bridge.protocol import extension as ext
from hexapod_bridge.protocol import legacy
from hexapod_bridge.protocol.stream import AMBIGUOUS_ACKS, HostParser
from hexapod_bridge.servos import SERVO_PING_FAILED

PRIORITY_ESTOP, PRIORITY_PING, PRIORITY_TRIAL, PRIORITY_MOVE, PRIORITY_UPLOAD = range(5)


@dataclass
class Outgoing:
    """A frame waiting to be sent or acknowledged."""

    frame: bytes
    priority: int
    seq: int | None = None  # extension frames wait for an ACK with this seq
    kind: int | None = None
    attempts: int = 0
    sent_at: float = -math.inf
    operation: 'Operation | None' = None
    ack_timeout: float | None = None  # None: the link's; a COMMIT waits for its compilation


@dataclass
class Operation:
    """An upload, trial start/stop or movement the caller can wait on."""

    name: str
    pending: int = 0
    done: bool = False
    ok: bool = False
    message: str = ''
    result: dict = field(default_factory=dict)
    unanswered: bool = False  # it failed as the robot stopped answering (the link's fault)

    def finish(self, ok: bool, message: str) -> None:
        """Mark the operation done with its outcome (only the first call counts)."""
        if not self.done:
            self.done, self.ok, self.message = True, ok, message


@dataclass
class LinkStats:
    """Counters of the host side of the radio link."""

    frames_sent: int = 0
    retries: int = 0
    pings_sent: int = 0
    acks: int = 0
    unexpected_acks: int = 0
    reports_missed: int = 0  # robot TRIAL reports lost (gaps in their sequence numbers)
    stale_reports: int = 0  # TRIAL reports that arrived for an earlier trial (ignored)


class RobotLink:
    """The host side of the radio link: queues, pacing, retries, acknowledgements, trial state."""

    def __init__(
        self,
        baud: int = 19200,
        ping_period: float = 1.0,
        ack_timeout: float = 0.25,
        max_retries: int = 6,
        upload_window: int = 4,
        firmware: str = 'v2',
        leg_map=ext.IDENTITY_LEG_MAP,
    ) -> None:
        if firmware not in ('v2', 'legacy'):
            raise ValueError("firmware must be 'v2' (gait-upload extension) or 'legacy'")
        self.parser = HostParser()
        self.firmware = firmware
        self.leg_map = ext.validate_leg_map(leg_map)
        self.bytes_per_second = baud / 10.0
        self.ping_period = ping_period
        self.ack_timeout = ack_timeout
        self.max_retries = max_retries
        self.upload_window = upload_window
        self.armed = False
        self.stats = LinkStats()
        self.last_heard = -math.inf
        self.last_telemetry: legacy.Telemetry | None = None
        self.trial_state: ext.TrialState = ext.TrialState.IDLE
        self.trial_elapsed = 0.0
        #: trials the robot acknowledged starting; a TRIAL report belongs to trial number
        #: ``trial_generation`` only when no newer start is awaiting its acknowledgement
        self.trial_generation = 0
        self._start_pending = False
        self.events: deque[tuple[str, Any]] = deque(maxlen=1000)
        self._tokens = 20.0
        self._last_poll: float | None = None
        self._next_ping = -math.inf
        self._seq = 0  # last sequence number used
        self._queue: list[Outgoing] = []  # waiting to be sent for the first time
        self._in_flight: dict[int, Outgoing] = {}  # seq -> sent, awaiting ACK
        self._upload_backlog: deque[Outgoing] = deque()
        self._movement_acks: dict[int, Operation] = {}
        self._gait_ids = itertools.count(1)
        self._robot_period = ext.FIRMWARE_GAIT_PERIOD  # of the gait the robot holds
        self._hellos: dict[int, Operation] = {}  # seq -> a HELLO waiting for its VERSION
        self._last_report_seq: int | None = None

    # -- commands ----------------------------------------------------------------------------
    def arm(self, on: bool, now: float) -> None:
        """Allow (True) or stop (False) transmission; nothing but an e-stop is sent unarmed."""
        self.armed = bool(on)
        if self.armed:
            self._next_ping = now
        self.events.append(('armed', self.armed))

    def _next_seq(self, count: int = 1) -> int:
        """Reserve ``count`` consecutive sequence numbers (mod 256); return the first."""
        first = (self._seq + 1) & 0xFF
        self._seq = (self._seq + count) & 0xFF
        return first

    def _command(self, kind: ext.Cmd, payload: bytes, priority: int, op: Operation) -> Outgoing:
        seq = self._next_seq()
        op.pending += 1
        return Outgoing(
            ext.encode_command(kind, seq, payload), priority, seq, int(kind), operation=op
        )

    def upload(self, gait) -> Operation:
        """
        Queue an upload of a hexapod_gait.GaitParameters.

        The Operation completes when the robot acknowledged the COMMIT (result: gait_id) or failed
        (message says why).
        """
        op = Operation('upload')
        if self.firmware == 'legacy':
            op.finish(
                False,
                'the legacy firmware cannot receive gait parameters over the radio '
                '(paste them into the firmware and reflash; see docs/radio-protocol.md)',
            )
            return op
        gait_id = next(self._gait_ids) & 0xFFFF
        values = ext.gait_values(gait, self.leg_map)
        frames = ext.upload_frames(values, gait_id, self._next_seq(ext.N_PARAMS + 1))
        # the robot answers a COMMIT once it compiled the table (and, if it fails, the last one
        # again): wait that long before sending it again
        compile_time = ext.commit_compile_time(gait.period, self._robot_period)
        for frame in frames:
            op.pending += 1
            timeout = self.ack_timeout + compile_time if frame[1] == ext.Cmd.COMMIT else None
            self._upload_backlog.append(
                Outgoing(
                    frame, PRIORITY_UPLOAD, frame[2], frame[1], operation=op, ack_timeout=timeout
                )
            )
        op.result['period'] = gait.period
        op.result['gait_id'] = gait_id
        op.result['values'] = ext.quantise(values)
        return op

    def hello(self) -> Operation:
        """
        Queue a HELLO; the Operation completes with the robot's VERSION (result: major, minor).

        The firmware module also checks its servos after a HELLO (reported as FF FD 0B <id>).
        """
        op = Operation('hello')
        if self.firmware == 'legacy':
            op.finish(False, 'the legacy firmware has no HELLO (and no servo health check)')
            return op
        if not self.armed:
            op.finish(False, 'not armed: call ~/arm first')
            return op
        seq = self._next_seq()
        self._hellos[seq] = op
        frame = ext.encode_command(ext.Cmd.HELLO, seq, bytes([ext.PROTOCOL_MAJOR]))
        self._queue.append(Outgoing(frame, PRIORITY_TRIAL))  # answered by VERSION, not an ACK
        return op

    def start_trial(self, duration: float, gait_id: int) -> Operation:
        """Ask the robot to walk gait ``gait_id`` for ``duration`` seconds."""
        op = Operation('start_trial')
        if self.firmware == 'legacy':
            # the only "start a trial" handle of today's firmware: reset restarts the 5 s walk
            return self.move(legacy.Movement(function=legacy.Function.RESET), op)
        try:
            payload = ext.start_payload(duration, gait_id)
        except ext.ExtensionError as exc:
            op.finish(False, str(exc))
            return op
        # A new trial starts from a clean state; until the robot acknowledges the start, reports
        # still in flight belong to the previous trial (the radio delivers bytes in order).
        self.trial_state, self.trial_elapsed = ext.TrialState.IDLE, 0.0
        self._start_pending = True
        self._queue.append(self._command(ext.Cmd.START_TRIAL, payload, PRIORITY_TRIAL, op))
        return op

    def stop_trial(self) -> Operation:
        """Ask the robot to stop walking."""
        op = Operation('stop_trial')
        if self.firmware == 'legacy':
            return self.move(
                legacy.Movement(direction=legacy.Direction.STOP, function=legacy.Function.STAND),
                op,
            )
        self._queue.append(self._command(ext.Cmd.STOP_TRIAL, b'', PRIORITY_TRIAL, op))
        return op

    def move(self, movement: legacy.Movement, op: Operation | None = None) -> Operation:
        """Queue a legacy movement frame (acknowledged by its checksum)."""
        op = op or Operation('movement')
        try:
            frame = legacy.encode_movement(movement)
            # The robot acknowledges with FF <checksum>; a checksum equal to a frame-type byte
            # would be read as that frame's header, so nudge the twist by 0.01 rad instead.
            nudge = 0.01
            while frame[9] in AMBIGUOUS_ACKS:
                frame = legacy.encode_movement(replace(movement, twist=movement.twist + nudge))
                nudge = -nudge if nudge > 0 else -nudge + 0.01
        except legacy.ProtocolError as exc:
            op.finish(False, str(exc))
            return op
        op.pending += 1
        self._movement_acks[frame[9]] = op
        self._queue.append(Outgoing(frame, PRIORITY_MOVE, operation=op))
        return op

    def set_telemetry_period(self, seconds: float) -> None:
        """Ask for attitude telemetry every ``seconds`` (legacy FF DD, unacknowledged)."""
        self._queue.append(Outgoing(legacy.encode_imu_period(seconds), PRIORITY_MOVE))

    def emergency_stop(self) -> Operation:
        """Sent at once, armed or not: three copies of ESTOP (v2) / motor power off (legacy)."""
        op = Operation('emergency_stop')
        for _ in range(3):
            if self.firmware == 'v2':
                seq = self._next_seq()
                frame = ext.encode_command(ext.Cmd.ESTOP, seq, b'')
            else:
                frame = legacy.encode_motor_power(False)
            self._queue.insert(0, Outgoing(frame, PRIORITY_ESTOP))
        op.finish(True, 'emergency stop sent')
        return op

    def motor_power(self, on: bool) -> Operation:
        """
        Switch the servos' power (legacy FF FA, unacknowledged: sent three times).

        Power on also clears a latched emergency stop, so trials can start again.
        """
        op = Operation('motor_power')
        if not self.armed:
            op.finish(False, 'not armed: call ~/arm first (an e-stop disarms the bridge)')
            return op
        for _ in range(3):
            self._queue.append(Outgoing(legacy.encode_motor_power(on), PRIORITY_TRIAL))
        op.finish(True, f'motor power {"on" if on else "off"} sent')
        return op

    # -- I/O ---------------------------------------------------------------------------------
    def poll(self, now: float) -> list[bytes]:
        """Frames to write now (paced to the radio's throughput, by priority)."""
        if self._last_poll is not None:
            self._tokens = min(
                20.0, self._tokens + (now - self._last_poll) * self.bytes_per_second
            )
        self._last_poll = now
        self._expire(now)
        out: list[bytes] = []
        while self._tokens >= legacy.FRAME_LEN:
            item = self._pick(now)
            if item is None:
                break
            out.append(item.frame)
            self._tokens -= legacy.FRAME_LEN
            self.stats.frames_sent += 1
            if item.attempts:
                self.stats.retries += 1
            item.attempts += 1
            item.sent_at = now
            if item.seq is not None:  # movement frames wait for their FF <sum> ack instead
                self._in_flight[item.seq] = item
        return out

    def _pick(self, now: float) -> Outgoing | None:
        if self._queue and self._queue[0].priority == PRIORITY_ESTOP:
            return self._queue.pop(0)
        if not self.armed:
            return None
        if now >= self._next_ping:
            self._next_ping = now + self.ping_period
            self.stats.pings_sent += 1
            return Outgoing(legacy.encode_ping(), PRIORITY_PING)
        for i, item in enumerate(self._queue):
            if item.priority <= PRIORITY_MOVE:
                return self._queue.pop(i)
        uploads_in_flight = sum(
            1 for o in self._in_flight.values() if o.priority == PRIORITY_UPLOAD
        )
        if self._upload_backlog and uploads_in_flight < self.upload_window:
            head = self._upload_backlog[0]
            if head.kind == ext.Cmd.COMMIT and uploads_in_flight:
                return None  # COMMIT only after every SET_PARAM of its set is acknowledged
            return self._upload_backlog.popleft()
        return None

    def _expire(self, now: float) -> None:
        for seq, item in list(self._in_flight.items()):
            timeout = self.ack_timeout if item.ack_timeout is None else item.ack_timeout
            if now - item.sent_at < timeout:
                continue
            if self._in_flight.pop(seq, None) is None:
                continue  # its upload failed earlier in this loop, which dropped it
            if item.attempts > self.max_retries:
                if item.kind == ext.Cmd.START_TRIAL:
                    self._start_pending = False  # no trial started: reports are the old one's
                if item.operation is not None and not item.operation.done:
                    item.operation.unanswered = True
                self._fail(item.operation, f'no acknowledgement after {item.attempts} attempts')
            elif item.priority == PRIORITY_UPLOAD:
                self._upload_backlog.appendleft(item)
            else:
                self._queue.append(item)

    def abandon(self, op: Operation, reason: str) -> None:
        """Give up an upload nobody waits for any more: its frames not yet sent are dropped."""
        self._fail(op, reason)

    def _fail(self, op: Operation | None, message: str) -> None:
        if op is None or op.done:
            return
        op.finish(False, message)
        if op.name == 'upload':
            self._upload_backlog = deque(o for o in self._upload_backlog if o.operation is not op)
            for seq in [s for s, o in self._in_flight.items() if o.operation is op]:
                del self._in_flight[seq]

    def receive(self, data: bytes, now: float) -> list:
        """Bytes from the radio at time ``now``: decode and handle frames; returns them."""
        frames = self.parser.feed(data)
        for frame in frames:
            self.last_heard = now
            self._handle(frame)
        return frames

    def _handle(self, frame) -> None:
        if isinstance(frame, ext.ReportFrame):
            if frame.type == ext.Report.ACK:
                self._on_ack(frame)
            elif frame.type == ext.Report.TRIAL:
                self.stats.reports_missed += ext.sequence_gap(self._last_report_seq, frame.seq)
                self._last_report_seq = frame.seq
                if self._start_pending or frame.payload[0] >= len(ext.TrialState):
                    self.stats.stale_reports += 1
                    return
                self.trial_state = ext.TrialState(frame.payload[0])
                self.trial_elapsed = int.from_bytes(frame.payload[1:4], 'big') / 1000.0
                self.events.append(('trial', (self.trial_state, self.trial_elapsed)))
            elif frame.type == ext.Report.VERSION:
                major, minor = frame.payload[0], frame.payload[1]
                self.events.append(('version', (major, minor)))
                op = self._hellos.pop(frame.seq, None)
                if op is not None:
                    op.result.update(major=major, minor=minor)
                    op.finish(True, f'the robot speaks protocol {major}.{minor}')
        elif isinstance(frame, legacy.MovementAck):
            op = self._movement_acks.pop(frame.checksum, None)
            if op is None:
                self.stats.unexpected_acks += 1
            else:
                self.stats.acks += 1
                op.finish(True, 'movement acknowledged')
        elif isinstance(frame, legacy.Telemetry):
            self.last_telemetry = frame
            self.events.append(('telemetry', frame))
        elif isinstance(frame, legacy.ErrorReport):
            if frame.location == SERVO_PING_FAILED:
                self.events.append(('servo_failure', frame.code))
            else:
                self.events.append(('error', frame.describe()))
        elif isinstance(frame, legacy.Text):
            self.events.append(('text', frame.text))
        elif isinstance(frame, legacy.ChargerStatus):
            self.events.append(('charger', frame))

    def _on_ack(self, frame: ext.ReportFrame) -> None:
        item = self._in_flight.pop(frame.seq, None)
        if item is None or item.kind != frame.payload[0]:
            self.stats.unexpected_acks += 1
            return
        self.stats.acks += 1
        op = item.operation
        status = frame.payload[1]
        if item.kind == ext.Cmd.START_TRIAL:
            self._start_pending = False
            if status == ext.Status.OK:
                self.trial_generation += 1
                self.trial_state, self.trial_elapsed = ext.TrialState.WALKING, 0.0
        if item.kind == ext.Cmd.COMMIT and status == ext.Status.OK and op is not None:
            self._robot_period = op.result.get('period', self._robot_period)
        if status != ext.Status.OK:
            name = ext.Status(status).name if status < len(ext.Status) else str(status)
            detail = ''
            if item.kind == ext.Cmd.SET_PARAM:
                detail = f' for parameter {ext.PARAM_NAMES[item.frame[3]]}'
            self._fail(op, f'robot refused {ext.Cmd(item.kind).name}{detail}: {name}')
            return
        if op is not None:
            op.pending -= 1
            if op.pending == 0:
                op.finish(True, f'{op.name} acknowledged')

    # -- status ------------------------------------------------------------------------------
    def queued_frames(self) -> list[bytes]:
        """Return the frames not sent yet (commands, then upload frames)."""
        return [item.frame for item in self._queue] + [item.frame for item in self._upload_backlog]

    def busy(self) -> bool:
        """Return True while frames wait to be sent or acknowledged."""
        return bool(self._queue or self._in_flight or self._upload_backlog)
