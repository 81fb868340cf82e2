# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A node's log lines that never straddle its context's shutdown.

A node's logger also publishes each line on ``/rosout``. A line logged by a worker thread while
the main thread shuts the context down reaches a publisher whose context is gone, and rcl adds a
line of its own to stderr ("Failed to publish log message to rosout: publisher's context is
invalid"; CI, 2026-12-07: an adaptation's "diagnosis after trial 1" as Ctrl-C stopped it). A
check of ``rclpy.ok()`` before each line cannot close that gap, so the two take one lock:
:func:`shutdown` shuts the context down holding it, and a :class:`GuardedLogging` node's logger
holds it for each line. A line logged after the shutdown goes to stderr, in the console's format,
without ``/rosout``.
"""

from __future__ import annotations

import os
import sys
import threading
import time
from typing import Any

import rclpy
from rclpy.impl import rcutils_logger
from rclpy.impl.rcutils_logger import RcutilsLogger
from rclpy.logging import LoggingSeverity

#: Held while the default context shuts down, and while a guarded logger writes a line.
CONTEXT_LOCK = threading.RLock()

# rclpy names a line's call site by the first frame outside its own logging files, and keeps the
# list open for wrappers like this one: the call site stays the node's code, not this file
# (rclpy's once/throttle filters and each site's fixed severity are keyed on it)
_HERE = os.path.realpath(__file__)
if _HERE not in rcutils_logger._internal_callers:
    rcutils_logger._internal_callers.append(_HERE)


class GuardedLogger(RcutilsLogger):
    """A node's logger whose lines are written while its context is up, or to stderr after."""

    def __init__(self, name: str, context: Any) -> None:
        super().__init__(name)
        self._context = context

    def log(self, message: Any, severity: Any, **kwargs: Any) -> bool:
        """Log as ``RcutilsLogger.log`` does while the context is up; to stderr after."""
        with CONTEXT_LOCK:
            if self._context.ok():
                return super().log(message, severity, **kwargs)
        if not self.is_enabled_for(severity):
            return False
        level = LoggingSeverity(severity).name
        line = f'[{level}] [{time.time():.9f}] [{self.name}]: {message}'
        print(line, file=sys.stderr, flush=True)
        return True

    def get_child(self, name: str) -> GuardedLogger:
        """Return a child logger, guarded as this one is."""
        return GuardedLogger(super().get_child(name).name, self._context)


class GuardedLogging:
    """A node mixin (before ``Node`` in its bases): its ``get_logger()`` is guarded."""

    def get_logger(self) -> GuardedLogger:
        """Return the node's logger, guarded against its context's shutdown."""
        guarded = self.__dict__.get('_guarded_logger')
        if guarded is None:
            plain = super().get_logger()  # type: ignore[misc]
            guarded = GuardedLogger(plain.name, self.context)  # type: ignore[attr-defined]
            self.__dict__['_guarded_logger'] = guarded
        return guarded


def shutdown() -> None:
    """Shut the default context down (if it is up) while no guarded line is being written."""
    with CONTEXT_LOCK:
        rclpy.try_shutdown()
