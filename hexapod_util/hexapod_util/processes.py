# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Child processes that do not outlive the process that started them (ROS-free)."""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
from pathlib import Path
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


@contextlib.contextmanager
def worker_pool(
    workers: int, initializer: Callable[[], None] = die_with_parent
) -> Iterator[cf.ProcessPoolExecutor]:
    """
    Open a process pool that a stop ends at once.

    Left normally, the pool shuts down as ``with ProcessPoolExecutor(...)`` does: it waits for its
    work. Left by an exception (the stop of a command, Ctrl-C, an error in the caller), it does
    not wait for the jobs its workers are running, which can take minutes: the jobs not started
    are cancelled and the workers terminated, so the command ends now and the exception goes on.
    """
    pool = cf.ProcessPoolExecutor(workers, initializer=initializer)
    try:
        yield pool
    except BaseException:
        terminate_workers(pool)
        raise
    pool.shutdown(wait=True)


def terminate_workers(pool: cf.ProcessPoolExecutor) -> None:
    """Cancel ``pool``'s jobs not started, terminate its workers, and shut it down, not waiting."""
    # (Python 3.14's pool.terminate_workers(); before it the pool keeps its workers privately,
    # and drops them on shutdown)
    processes = list((getattr(pool, '_processes', None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        if process.is_alive():
            process.terminate()
    for process in processes:
        process.join(timeout=5.0)


#: [s] how often a wait for a pool's job looks at its ``stop``.
STOP_POLL_S = 0.2


class Stopped(Exception):
    """Raised by :func:`map_in_workers` and :func:`result_unless_stopped` once ``stop()`` held."""


def result_unless_stopped(
    future: cf.Future[R], stop: Callable[[], bool] | None, poll_s: float = STOP_POLL_S
) -> R:
    """Return ``future``'s result; raise :class:`Stopped` as soon as ``stop()`` holds first."""
    while True:
        if stop is not None and stop():
            raise Stopped
        try:
            return future.result(timeout=None if stop is None else poll_s)
        except cf.TimeoutError:
            continue


def map_in_workers(
    fn: Callable[[T], R],
    jobs: Sequence[T],
    workers: int,
    stop: Callable[[], bool] | None = None,
) -> Iterator[R]:
    """
    Yield ``fn(job)`` for each job, in order: in this process (``workers`` <= 1) or in a pool.

    The pool's processes die with this one (:func:`die_with_parent`), and with a stop of the
    caller (:func:`worker_pool`); ``fn`` must be picklable. ``stop()``, asked before each job in
    this process, and every :data:`STOP_POLL_S` while a pool's job is awaited, raises
    :class:`Stopped` (a pool's processes are then ended at once).
    """
    if workers <= 1:
        for job in jobs:
            if stop is not None and stop():
                raise Stopped
            yield fn(job)
        return
    with worker_pool(workers) as pool:
        # (not pool.map: closed early, its iterator cancels the jobs itself, and Python 3.11's
        # pool then fails to mark them broken as it terminates, with a traceback in its thread)
        futures = [pool.submit(fn, job) for job in jobs]
        for future in futures:
            yield result_unless_stopped(future, stop)


def child_pids(pid: int) -> set[int]:
    """Return the processes ``pid`` has started and that still exist (Linux /proc; else none)."""
    found: set[int] = set()
    for stat in Path('/proc').glob('[0-9]*/stat'):
        try:
            if int(_stat_fields(stat.read_text())[1]) == pid:
                found.add(int(stat.parent.name))
        except (OSError, ValueError, IndexError):
            pass  # a process that ended while being read
    return found


def is_running(pid: int) -> bool:
    """Return whether ``pid`` runs: it exists and has not exited (a zombie not reaped has)."""
    try:
        stat = Path(f'/proc/{pid}/stat').read_text()
    except FileNotFoundError:
        return False
    return _stat_fields(stat)[0] not in ('Z', 'X')


def _stat_fields(stat: str) -> list[str]:
    """Return a /proc/PID/stat line's fields after the command name: state, parent, ..."""
    return stat.rsplit(')', 1)[1].split()
