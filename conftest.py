# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Every test process's home is a temporary directory of its own.

Nodes and commands write under HOME (the damage-informed prior's cache in ~/.cache, ROS logs and
recordings under ~/.ros, matplotlib's cache): a test must neither leave files there nor read
what an earlier run left, so each pytest process (each xdist worker too) gets a fresh HOME,
removed at its end.
"""

from __future__ import annotations

import os
from pathlib import Path
import shutil
import tempfile

_HOME: dict[str, str] = {}
#: what lives under HOME, each pointed into the temporary one
_UNDER_HOME = (('XDG_CACHE_HOME', '.cache'), ('ROS_HOME', '.ros'), ('MPLCONFIGDIR', '.mpl'))


def pytest_configure(config) -> None:
    home = tempfile.mkdtemp(prefix='hexapod-test-home-')
    _HOME['path'] = home
    for name, sub in _UNDER_HOME:
        Path(home, sub).mkdir()
        os.environ[name] = str(Path(home, sub))
    os.environ['HOME'] = home


def pytest_unconfigure(config) -> None:
    shutil.rmtree(_HOME.pop('path', ''), ignore_errors=True)
