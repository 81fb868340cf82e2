# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Atomic writes: a reader sees the old file or the complete new one, never a part."""

from __future__ import annotations

import contextlib
import os
from pathlib import Path
import tempfile
from typing import Any, BinaryIO, Iterator


@contextlib.contextmanager
def atomic_output(path: str | os.PathLike) -> Iterator[BinaryIO]:
    """
    Return a binary file to write ``path`` through.

    Readers see the old file or the complete new one, never a part (temporary file in the same
    directory, fsync, rename, directory fsync). If the block raises, the old file stays and the
    temporary is removed.
    """
    path = Path(path)
    directory = path.parent if str(path.parent) else Path('.')
    directory.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f'.{path.name}.', suffix='.tmp', dir=directory)
    try:
        umask = os.umask(0)
        os.umask(umask)
        os.fchmod(fd, 0o666 & ~umask)  # mkstemp makes 0600; a map is an ordinary file
        with os.fdopen(fd, 'wb') as fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    with contextlib.suppress(OSError):  # directory fsync: not possible on every filesystem
        dfd = os.open(directory, os.O_RDONLY)
        try:
            os.fsync(dfd)
        finally:
            os.close(dfd)


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically (see :func:`atomic_output`)."""
    with atomic_output(path) as fh:
        fh.write(data)


def copy_whole_rows(src: str | os.PathLike, dest: str | os.PathLike) -> None:
    """Copy a JSON-lines log up to its last whole row (a row being written is torn), atomically."""
    data = Path(src).read_bytes()
    atomic_write_bytes(dest, data[: data.rfind(b'\n') + 1])


def save_png(fig: Any, out: str | os.PathLike) -> Path:
    """Write a matplotlib figure to ``out`` as a PNG, atomically, and close it."""
    import matplotlib.pyplot as plt  # here: importing this module costs no matplotlib

    out = Path(out)
    with atomic_output(out) as fh:
        fig.savefig(fh, format='png', dpi=110, bbox_inches='tight')
    plt.close(fig)
    return out


def ros_home() -> Path:
    """Return ROS_HOME, where ROS 2 keeps a user's logs (default ``~/.ros``)."""
    return Path(os.environ.get('ROS_HOME') or Path.home() / '.ros').expanduser()


def under_ros_home(directory: str | os.PathLike) -> Path:
    """Return ``directory`` as a node writes to it: a relative one lies under ROS_HOME."""
    path = Path(directory).expanduser()
    return path if path.is_absolute() else ros_home() / path
