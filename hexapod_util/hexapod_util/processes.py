# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Child processes that do not outlive the process that started them (ROS-free)."""

from __future__ import annotations

import concurrent.futures as cf
import signal
import sys
from typing import Callable, Iterator, Sequence, TypeVar

T = TypeVar('T')
R = TypeVar('R')


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


def map_in_workers(fn: Callable[[T], R], jobs: Sequence[T], workers: int) -> Iterator[R]:
    """
    Yield ``fn(job)`` for each job, in order: in this process (``workers`` <= 1) or in a pool.

    The pool's processes die with this one (:func:`die_with_parent`); ``fn`` must be picklable.
    """
    if workers <= 1:
        yield from map(fn, jobs)
        return
    with cf.ProcessPoolExecutor(workers, initializer=die_with_parent) as pool:
        yield from pool.map(fn, jobs)
