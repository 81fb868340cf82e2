# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Reading ``.npz`` files that may be damaged: one error for every way their bytes can be bad.

numpy's readers raise many kinds of exception on damaged bytes (BadZipFile, EOFError,
ValueError, zlib.error, tokenize.TokenError, MemoryError, ...); a caller needs one answer for
all of them. Pickles are never loaded.
"""

from __future__ import annotations

import errno
import io
import json
import os
from pathlib import Path
from typing import Any, Sequence

from hexapod_util.files import atomic_write_bytes
import numpy as np


class UnreadableFile(ValueError):
    """An ``.npz`` file whose bytes are damaged or that lacks an array (the text says which)."""


def read_npz(
    path: str | os.PathLike, names: Sequence[str], optional: Sequence[str] = ()
) -> dict[str, np.ndarray]:
    """
    Return the arrays ``names``, and those of ``optional`` the file holds, of the file ``path``.

    FileNotFoundError if there is no file there; UnreadableFile, naming the file and the problem,
    for every other way it cannot be read.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(errno.ENOENT, 'no such file', str(path))
    return _read(path, str(path), names, optional)


def read_npz_bytes(
    data: bytes, where: str, names: Sequence[str], optional: Sequence[str] = ()
) -> dict[str, np.ndarray]:
    """As :func:`read_npz`, for an ``.npz`` held in memory (``where`` names it in errors)."""
    return _read(io.BytesIO(data), where, names, optional)


def _read(
    source: Path | io.BytesIO, where: str, names: Sequence[str], optional: Sequence[str]
) -> dict[str, np.ndarray]:
    try:
        loaded = np.load(source, allow_pickle=False)
        if not isinstance(loaded, np.lib.npyio.NpzFile):
            raise UnreadableFile(f'{where}: a single array, not an .npz archive of named arrays')
        with loaded as data:
            missing = [name for name in names if name not in data.files]
            if missing:
                raise UnreadableFile(f'{where}: missing {", ".join(missing)}')
            wanted = [*names, *(name for name in optional if name in data.files)]
            return {name: np.asarray(data[name]) for name in wanted}
    except UnreadableFile:
        raise
    except Exception as exc:  # noqa: BLE001 - numpy's readers raise many kinds on damaged bytes
        raise UnreadableFile(
            f'{where}: truncated or corrupted ({type(exc).__name__}: {exc})'
        ) from exc


def json_array(array: np.ndarray, what: str) -> Any:
    """Return the JSON value held as one string in ``array``; UnreadableFile says what is wrong."""
    if array.shape != () or array.dtype.kind not in 'US':
        raise UnreadableFile(f'{what} must be one JSON string, found {array.dtype} {array.shape}')
    try:
        return json.loads(str(array))
    except (json.JSONDecodeError, RecursionError) as exc:
        raise UnreadableFile(f'{what} is not valid JSON ({exc})') from None


def float_array(array: np.ndarray, what: str) -> np.ndarray:
    """Return ``array`` as floats; UnreadableFile if it does not hold numbers."""
    if array.dtype.kind not in 'fiu':
        raise UnreadableFile(f'{what} must hold numbers, found dtype {array.dtype}')
    return array.astype(float)


def write_npz(
    path: str | os.PathLike, arrays: dict[str, np.ndarray], compressed: bool = False
) -> None:
    """Write ``arrays`` as an ``.npz`` atomically (compressed: zlib, for files kept in git)."""
    buf = io.BytesIO()
    (np.savez_compressed if compressed else np.savez)(buf, **arrays)
    atomic_write_bytes(path, buf.getvalue())


def compress_npz(src: str | os.PathLike, dest: str | os.PathLike) -> None:
    """Copy an ``.npz`` to ``dest`` atomically with the same arrays, compressed."""
    with np.load(src, allow_pickle=False) as data:
        write_npz(dest, {k: data[k] for k in data.files}, compressed=True)
