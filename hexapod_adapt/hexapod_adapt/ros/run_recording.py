# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The recording policy of an adaptation run (no node, no executor: unit-tested without a graph).

A run's MCAP file starts with the latest message of every latched topic (the URDF, the static
frames), then takes whatever the run records. Every message type the run will record is resolved
when the recording starts: a type whose definition cannot be found is refused then, by name, and
its topics are not recorded; the rest is. After that, nothing the recording does can stop the run
or the node: a failed write ends the recording of that run, and :attr:`RunRecording.problem` says
why, for the goal's result, the log and ``adapt/trials``.
"""

from __future__ import annotations

import os
from pathlib import Path
import threading
from typing import Any, Callable, Mapping

from hexapod_util.recording import (
    create_recording,
    McapRecorder,
    RecordingClosed,
    SchemaUnavailable,
)


class RunRecording:
    """
    One node's recording of its runs: at most one file open at a time.

    ``resolve(topic)`` gives the name a topic is recorded under (the node's fully qualified name);
    ``now_ns()`` the log time (the node's clock: sim time in a simulated graph).
    """

    def __init__(
        self,
        resolve: Callable[[str], str],
        now_ns: Callable[[], int],
        log_error: Callable[[str], None],
    ) -> None:
        self._resolve = resolve
        self._now_ns = now_ns
        self._log_error = log_error
        self._lock = threading.Lock()  # latched messages and the open file change together
        self._latched: dict[str, Any] = {}
        self._recorder: McapRecorder | None = None
        self._refused: set[str] = set()  # topics whose type has no definition this run
        self.problem = ''  # why this run's recording is incomplete or off ('' if it is not)

    @property
    def recording(self) -> bool:
        """Whether a file is open."""
        return self._recorder is not None

    @property
    def latched_topics(self) -> set[str]:
        """Latched topics received so far."""
        with self._lock:
            return set(self._latched)

    def on_latched(self, topic: str, msg: Any) -> None:
        """Keep the latest message of a latched topic; record it too if a run records."""
        with self._lock:
            self._latched[topic] = msg
            self._write(topic, msg)

    def start(
        self,
        directory: str | os.PathLike,
        types: Mapping[str, str],
        prefix: str = 'adapt',
        qos: Mapping[str, Any] | None = None,
    ) -> Path | None:
        """
        Open a new file in ``directory`` for a run that records ``types`` (topic -> pkg/msg/Type).

        ``qos`` (topic -> QoSProfile) goes into each channel's ``offered_qos_profiles``.

        The file is named ``<prefix>_<UTC date-time>.mcap``.

        Returns its path, or None when nothing can be recorded (:attr:`problem` says why). The
        latched messages are written first.
        """
        self.stop()
        self.problem = ''
        try:
            recorder = create_recording(
                Path(directory).expanduser(),
                prefix,
                {self._resolve(topic): profile for topic, profile in (qos or {}).items()},
            )
        except OSError as exc:
            return self._fail(f'cannot record in {directory}: {exc}; running without a recording')
        refused: dict[str, list[str]] = {}
        for topic, name in types.items():
            try:
                recorder.register_type(name)
            except SchemaUnavailable as exc:
                refused.setdefault(str(exc), []).append(topic)
        if refused:
            self.problem = '; '.join(
                f'not recording {", ".join(sorted(topics))}: {why}'
                for why, topics in sorted(refused.items())
            )
            self._log_error(f'recording {recorder.path}: {self.problem}')
        with self._lock:
            self._refused = {topic for topics in refused.values() for topic in topics}
            self._recorder = recorder
            for topic, msg in self._latched.items():
                self._write(topic, msg)
        return recorder.path if self._recorder is recorder else None

    def record(self, topic: str, msg: Any) -> None:
        """Record one message if a run records (never raises)."""
        if self._recorder is None:
            return
        with self._lock:
            self._write(topic, msg)

    def checkpoint(self) -> None:
        """Make what was recorded durable (after every trial); a failure ends the recording."""
        recorder = self._recorder
        if recorder is None:
            return
        try:
            recorder.checkpoint()
        except (OSError, RuntimeError) as exc:
            self._disable(
                recorder, f'recording to {recorder.path} failed: {exc}; recording stopped'
            )

    def stop(self) -> None:
        """Finish the open file, if any (end of a run, Ctrl-C, SIGTERM)."""
        with self._lock:
            recorder, self._recorder = self._recorder, None
        if recorder is not None:
            try:
                recorder.close()
            except (OSError, RuntimeError) as exc:
                self._fail(f'recording to {recorder.path} could not be finished: {exc}')

    # -- internals (called with the lock held) ---------------------------------------------
    def _write(self, topic: str, msg: Any) -> None:
        recorder = self._recorder
        if recorder is None or topic in self._refused:
            return
        try:
            recorder.record(self._resolve(topic), msg, log_time_ns=self._now_ns())
        except RecordingClosed:
            pass  # a sensor message that came as the run ended: the run's file is complete
        except SchemaUnavailable as exc:  # a type not declared at the start
            self._refused.add(topic)
            self._note(f'not recording {topic}: {exc}')
        except (OSError, RuntimeError, ValueError, TypeError) as exc:
            self._recorder = None
            self._fail(f'recording to {recorder.path} failed: {exc}; recording stopped')
            try:
                recorder.close()
            except (OSError, RuntimeError):
                pass  # the file keeps every checkpointed trial; recover_recording indexes it

    def _disable(self, recorder: McapRecorder, why: str) -> None:
        with self._lock:
            if self._recorder is recorder:
                self._recorder = None
        self._fail(why)
        try:
            recorder.close()
        except (OSError, RuntimeError, ValueError):
            pass  # the file keeps every checkpointed trial; recover_recording indexes it

    def _note(self, why: str) -> None:
        self.problem = f'{self.problem}; {why}' if self.problem else why
        self._log_error(why)

    def _fail(self, why: str) -> None:
        self._note(why)
        return None
