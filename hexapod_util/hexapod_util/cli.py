# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
What every console command of the project does the same way (no ROS needed).

* Numbers: :func:`number` is an argparse ``type`` that refuses a value outside its range, or not
  finite, with the range in the message (argparse then exits with status 2).
* Paths: :func:`input_file`, :func:`output_file` and :func:`output_dir` check a path before any
  work starts: a missing file, a directory where a file is expected, a file where a directory is
  expected, or a place that cannot be written, each named.
* Files a command writes follow one rule: an existing output is refused unless a flag says what
  to do with it (:func:`claim_outputs`: ``--force`` keeps the old file as ``NAME.bak``), and an
  input is never modified unless a flag says so. :func:`open_for_writing_by` finds a process
  still writing a file (a recording in progress).
* :func:`run_command` runs a command's body so that bad input and the normal signals end it with
  one line on stderr that names the problem, and a non-zero status: an OSError or ValueError
  (status 1), Ctrl-C / SIGINT (130) and SIGTERM (143). SIGTERM is raised as :class:`Terminated`,
  a KeyboardInterrupt, so the clean-up a command does for Ctrl-C (a map's last checkpoint kept, a
  recording finished) runs for it too. A programming error still shows its traceback.

  Python drops an exception raised where it cannot propagate (a destructor, a weakref callback
  such as the import system's module-lock clean-up) and reports it through
  ``sys.unraisablehook``. A signal that lands there would be lost, and the command would run on:
  :func:`run_command` sends such a dropped stop to itself again, so it ends the command as soon
  as the interpreter is back in ordinary code.

  A library can also catch the KeyboardInterrupt a signal raised and run on. A stop that has not
  ended the command, nor been taken in hand by it (:func:`acknowledge_stop`, for a clean-up that
  takes a while), within :data:`RESEND_AFTER_S` seconds is sent again.
"""

from __future__ import annotations

import argparse
import gc
import math
import os
from pathlib import Path
import signal
import sys
import tempfile
import threading
from typing import Callable, Iterable

#: Exit status of a command ended by SIGINT (Ctrl-C) or SIGTERM: 128 + the signal number.
STATUS_INTERRUPTED = 128 + signal.SIGINT
STATUS_TERMINATED = 128 + signal.SIGTERM


#: A stop the command has neither ended on nor acknowledged is sent again after this many seconds.
RESEND_AFTER_S = 20.0


class Terminated(KeyboardInterrupt):
    """SIGTERM: stops a command the way Ctrl-C does."""


#: The running command's "the stop is in hand" event (None: no command runs in this process).
_in_hand: threading.Event | None = None


def acknowledge_stop() -> None:
    """
    Say that the running command has its stop in hand: it is not sent again.

    For a command that catches KeyboardInterrupt to clean up (a goal cancelled, completed runs
    written) before it re-raises.
    """
    if _in_hand is not None:
        _in_hand.set()


def number(
    kind: type = float,
    low: float | None = None,
    high: float | None = None,
    *,
    low_open: bool = False,
    high_open: bool = False,
) -> Callable[[str], float]:
    """
    Return an argparse ``type``: a finite ``kind`` in [low, high] (or open at either end).

    The refusal says the range: ``must be in (0, 60], got 61``.
    """

    def parse(text: str):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f'{"an integer" if kind is int else "a number"} expected, got {text!r}'
            ) from None
        if kind is float and not math.isfinite(value):
            raise argparse.ArgumentTypeError(f'a finite number expected, got {text!r}')
        below = low is not None and (value <= low if low_open else value < low)
        above = high is not None and (value >= high if high_open else value > high)
        if below or above:
            raise argparse.ArgumentTypeError(
                f'must be in {interval(low, high, low_open, high_open)}, got {text}'
            )
        return value

    parse.__name__ = kind.__name__  # argparse names the type in its messages
    return parse


def interval(low, high, low_open: bool = False, high_open: bool = False) -> str:
    """Return a range as written in messages: ``[1, 60]``, ``(0, inf)``."""
    lo = '-inf' if low is None else _text(low)
    hi = 'inf' if high is None else _text(high)
    opening = '(' if low_open or low is None else '['
    closing = ')' if high_open or high is None else ']'
    return f'{opening}{lo}, {hi}{closing}'


def _text(value: float) -> str:
    return str(value) if isinstance(value, int) else f'{value:g}'


def _writable_dir_problem(directory: Path) -> str:
    """Say why files cannot be created in ``directory`` (created if missing; '' if they can)."""
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        return f'{directory} is not a directory'
    except OSError as exc:
        return f'cannot create directory {directory}: {exc.strerror}'
    if not directory.is_dir():
        return f'{directory} is not a directory'
    try:  # os.access says yes to root on a read-only file system: try it
        with tempfile.TemporaryFile(dir=directory):
            pass
    except OSError as exc:
        return f'cannot write in {directory}: {exc.strerror}'
    return ''


def input_file(text: str) -> Path:
    """Argparse ``type``: an existing, readable file."""
    path = Path(text).expanduser()
    if path.is_dir():
        raise argparse.ArgumentTypeError(f'{path} is a directory, not a file')
    if not path.is_file():
        raise argparse.ArgumentTypeError(f'{path}: no such file')
    if not os.access(path, os.R_OK):
        raise argparse.ArgumentTypeError(f'{path}: permission denied')
    return path


def output_file(text: str) -> Path:
    """Argparse ``type``: a file that can be written (its directory is created if missing)."""
    path = Path(text).expanduser()
    if path.is_dir():
        raise argparse.ArgumentTypeError(f'{path} is a directory, not a file')
    problem = _writable_dir_problem(path.parent)
    if problem:
        raise argparse.ArgumentTypeError(problem)
    return path


def output_dir(text: str) -> Path:
    """Argparse ``type``: a directory files can be written in (created if missing)."""
    path = Path(text).expanduser()
    problem = _writable_dir_problem(path)
    if problem:
        raise argparse.ArgumentTypeError(problem)
    return path


#: What an output a command replaced (``--force``) is kept as: ``NAME`` + this.
BACKUP_SUFFIX = '.bak'


class OutputExists(ValueError):
    """An output a command would replace, when no flag says what to do with it."""


def backup_path(path: Path) -> Path:
    """Return where ``--force`` keeps the file it replaces (``NAME.bak``)."""
    return path.with_name(path.name + BACKUP_SUFFIX)


def claim_outputs(paths: Iterable[Path], force: bool, flags: str = '--force') -> list[Path]:
    """
    Apply the output rule to the files a command is about to write.

    None exists: nothing to do. Some exist and ``force`` is false: :class:`OutputExists` names them
    and ``flags`` (what the user may pass, e.g. "--resume to continue it, or --force"), and
    nothing is touched. ``force``: each existing file is renamed to ``NAME.bak`` (replacing an
    older backup) before the command writes; returns those backups.
    """
    existing = [p for p in dict.fromkeys(Path(p) for p in paths) if p.exists()]
    if not existing:
        return []
    if not force:
        names = ', '.join(str(p) for p in existing)
        raise OutputExists(f'{names} already exist{"s" if len(existing) == 1 else ""}: {flags}')
    backups = []
    for path in existing:
        backup = backup_path(path)
        os.replace(path, backup)
        backups.append(backup)
    return backups


def _write_flags(pid: str, fd: str) -> bool:
    """Whether descriptor ``fd`` of process ``pid`` is open for writing (Linux /proc)."""
    try:
        for line in Path(f'/proc/{pid}/fdinfo/{fd}').read_text().splitlines():
            if line.startswith('flags:'):
                return bool(int(line.split()[1], 8) & (os.O_WRONLY | os.O_RDWR))
    except (OSError, ValueError, IndexError):
        pass
    return False


def open_for_writing_by(path: Path) -> list[int]:
    """
    Return the ids of the processes that hold ``path`` open for writing (this one excepted).

    Read from /proc (Linux); elsewhere, or for processes this user cannot inspect, none are
    found.
    """
    target = Path(path).resolve()
    found = []
    for proc in Path('/proc').glob('[0-9]*'):
        if proc.name == str(os.getpid()):
            continue
        try:
            fds = list((proc / 'fd').iterdir())
        except OSError:
            continue
        for fd in fds:
            try:
                if Path(os.readlink(fd)) == target and _write_flags(proc.name, fd.name):
                    found.append(int(proc.name))
                    break
            except OSError:
                continue
    return found


def os_error_text(exc: OSError) -> str:
    """Return an OSError as one line: what failed and on which path."""
    if exc.filename is not None and exc.strerror:
        if exc.filename2 is not None:  # symlink, rename: name both
            return f'{exc.strerror}: {exc.filename} -> {exc.filename2}'
        return f'{exc.strerror}: {exc.filename}'
    return str(exc) or type(exc).__name__


def _stop_handler(in_hand: threading.Event, resend_after: float) -> Callable:
    """
    Make the handler of SIGINT and SIGTERM: raise the stop, and send it again while not in hand.

    A forked worker inherits the handler but not the resending: in it the stop is only raised.
    """
    pid = os.getpid()
    armed: set[int] = set()
    lock = threading.Lock()

    def resend(signum: int) -> None:
        while not in_hand.wait(resend_after):
            os.kill(pid, signum)

    def handler(signum, frame) -> None:
        if os.getpid() == pid:
            with lock:
                if signum not in armed:
                    armed.add(signum)
                    threading.Thread(
                        target=resend, args=(signum,), name='stop-resend', daemon=True
                    ).start()
        raise Terminated() if signum == signal.SIGTERM else KeyboardInterrupt()

    return handler


def _stop_signal(exc: BaseException | None) -> int | None:
    """Return the signal a dropped exception stood for (None: not a stop)."""
    if isinstance(exc, Terminated):
        return signal.SIGTERM
    if isinstance(exc, KeyboardInterrupt):
        return signal.SIGINT
    return None


def _redeliver_dropped_stops(previous: Callable, stopped: threading.Event) -> Callable:
    """
    Make an unraisable hook: a dropped stop is sent again, the rest go to ``previous``.

    Once ``stopped`` is set (the command was stopped and said so), the rest are dropped quietly:
    a signal can land inside a constructor (e.g. a ZipFile's, opening a cache file) and leave an
    object whose destructor then fails, and the stop promises one line, not its traceback.
    """

    def hook(unraisable) -> None:
        signum = _stop_signal(unraisable.exc_value)
        if signum is None:
            if not stopped.is_set():
                previous(unraisable)
            return
        # not from inside the hook (the new exception would be dropped too): a moment later, from
        # another thread; the handler then runs in the main thread's ordinary code
        timer = threading.Timer(0.05, os.kill, (os.getpid(), signum))
        timer.daemon = True
        timer.start()

    return hook


def run_command(
    prog: str,
    body: Callable[[], int],
    stopped_note: str = '',
    resend_after: float = RESEND_AFTER_S,
) -> int:
    """
    Run a command's ``body`` and return its exit status; see the module docstring.

    ``stopped_note`` is added to the line printed when a signal stops the command (e.g. how to
    resume); a stop neither ended on nor acknowledged in ``resend_after`` s is sent again.
    """
    global _in_hand
    previous: dict[int, object] = {}
    previous_hook = sys.unraisablehook
    previous_in_hand = _in_hand
    stopped = threading.Event()
    if threading.current_thread() is threading.main_thread():
        handler = _stop_handler(stopped, resend_after)
        previous[signal.SIGTERM] = signal.signal(signal.SIGTERM, handler)
        # Ctrl-C is left alone where it is ignored (a command started with nohup ... &)
        if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
            previous[signal.SIGINT] = signal.signal(signal.SIGINT, handler)
        sys.unraisablehook = _redeliver_dropped_stops(previous_hook, stopped)
        _in_hand = stopped
    note = f'; {stopped_note}' if stopped_note else ''
    try:
        return body()
    except Terminated:
        stopped.set()
        _say(prog, f'terminated (SIGTERM){note}')
        return STATUS_TERMINATED
    except KeyboardInterrupt:
        stopped.set()
        _say(prog, f'interrupted (SIGINT){note}')
        return STATUS_INTERRUPTED
    except OSError as exc:
        _say(prog, os_error_text(exc))
        return 1
    except ValueError as exc:
        _say(prog, str(exc) or type(exc).__name__)
        return 1
    finally:
        if previous:
            if stopped.is_set():
                gc.collect()  # what the stop left half built goes now, under the quiet hook
            for signum, before in previous.items():
                signal.signal(signum, before)
            sys.unraisablehook = previous_hook
            _in_hand = previous_in_hand
        stopped.set()  # the command is over: nothing is sent again


def _say(prog: str, text: str) -> None:
    """Print ``prog: text`` on stderr as one line."""
    line = ' '.join(text.split())
    try:
        print(f'{prog}: {line}', file=sys.stderr, flush=True)
    except OSError:
        pass  # stderr is gone (a closed pipe): the status still says it


#: What a refused output tells the user to do (commands without --resume).
FORCE_HINT = '--force to replace it (the old file is kept as NAME.bak)'


def add_force(parser: argparse.ArgumentParser) -> None:
    """Add the output rule's ``--force`` to a command that writes files."""
    parser.add_argument(
        '--force',
        action='store_true',
        help='replace outputs that exist (each old file is kept as NAME.bak)',
    )
