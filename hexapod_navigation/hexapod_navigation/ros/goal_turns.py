# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Which goal may walk: the newest one, one at a time (navigate_node's goal arbitration).

As nav2's action servers do, a new goal preempts the one being pursued, and every goal that was
superseded before its turn ends without walking. A goal walks only once it has been the newest for
``settle_s``, so a burst of goals (an operator clicking again and again) walks only its last. A
goal waiting for its turn holds no lock that the node's other callbacks need; it wakes as soon as
it is superseded, cancelled or the node closes. ROS-free, so it is tested on its own.
"""

from __future__ import annotations

import threading
import time
from typing import Callable, Hashable


class GoalTurns:
    """The newest accepted goal walks; older ones stop (the walking one) or never start."""

    def __init__(self, settle_s: float = 0.0) -> None:
        self.settle_s = settle_s
        self._cond = threading.Condition()
        self._newest: Hashable | None = None
        self._newest_since = 0.0  # time.monotonic() when the newest goal was accepted
        self._active: Hashable | None = None
        self._closing = False

    def accepted(self, key: Hashable) -> None:
        """Take an accepted goal: it is now the newest, and supersedes all others."""
        with self._cond:
            self._newest = key
            self._newest_since = time.monotonic()
            self._cond.notify_all()

    def superseded(self, key: Hashable) -> bool:
        """Return True if a newer goal was accepted, or the node is closing."""
        with self._cond:
            return self._closing or key != self._newest

    def wait_turn(
        self, key: Hashable, cancelled: Callable[[], bool], poll_s: float = 0.05
    ) -> bool:
        """
        Wait until ``key`` may walk: True when its turn came (it is then the active goal).

        Its turn comes when no goal walks and it has been the newest for ``settle_s``. False, at
        once, when it was superseded, cancelled or the node is closing: it must end unwalked.
        """
        with self._cond:
            while True:
                if self._closing or key != self._newest or cancelled():
                    return False
                settling = self._newest_since + self.settle_s - time.monotonic()
                if self._active is None and settling <= 0:
                    self._active = key
                    return True
                self._cond.wait(min(poll_s, settling) if settling > 0 else poll_s)

    def done(self, key: Hashable) -> None:
        """End the walking goal: the next may walk."""
        with self._cond:
            if self._active == key:
                self._active = None
            self._cond.notify_all()

    @property
    def walking(self) -> bool:
        """Return True while a goal walks."""
        with self._cond:
            return self._active is not None

    def close(self, timeout_s: float) -> bool:
        """Stop every goal (the walking one at its next check); True if it ended in time."""
        deadline = time.monotonic() + timeout_s
        with self._cond:
            self._closing = True
            self._cond.notify_all()
            while self._active is not None:
                left = deadline - time.monotonic()
                if left <= 0:
                    return False
                self._cond.wait(left)
        return True
