# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Child processes that do not outlive the process that started them (ROS-free)."""

from __future__ import annotations

import signal
import sys


def die_with_parent() -> None:
    """
    Ask the kernel to stop this process (SIGTERM) when the thread that started it exits.

    For ``subprocess.Popen(preexec_fn=...)`` in scripts that start nodes, and as the
    ``initializer`` of worker pools: if the parent is killed outright (SIGKILL, a test's timeout, a
    closed terminal), its children do not run on as orphans. The kernel watches the thread that
    forked, so start the children from a thread that lives as long as they are needed. The
    SIGTERM then ends the process at once: a handler inherited from the parent by a forked worker
    (the commands' "terminated" handler) is dropped, as it let a pool worker catch the signal and
    run on. Linux only; a no-op elsewhere.
    """
    if not sys.platform.startswith('linux'):
        return
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    import ctypes

    pr_set_pdeathsig = 1
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(pr_set_pdeathsig, signal.SIGTERM, 0, 0, 0)
