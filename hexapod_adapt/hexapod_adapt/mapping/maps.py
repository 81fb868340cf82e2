# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The maps shipped with hexapod_adapt: where they are, installed or in the source tree.

The default map (10,000 niches, 1,000,000 MuJoCo evaluations; hexapod_adapt/maps/README.md says
how it was made) is what adapt_node, the launch files, run_experiment and ``make demo`` use
unless told otherwise. The small demo map is kept for tests.
"""

from __future__ import annotations

from pathlib import Path

PACKAGE = 'hexapod_adapt'
DEFAULT_MAP = 'default_map.npz'
DEMO_MAP = 'demo_map.npz'
CEILINGS = 'ceilings'  # the default map's cached ceilings (hexapod_adapt.online.ceiling)


#: The workspace's source tree (this file is <ws>/hexapod_adapt/hexapod_adapt/mapping/maps.py).
_SOURCE_TREE = Path(__file__).resolve().parents[3]


def _candidates(name: str, package: str = PACKAGE) -> list[Path]:
    found = []
    try:
        from ament_index_python.packages import get_package_share_directory, PackageNotFoundError

        try:
            found.append(Path(get_package_share_directory(package)) / 'maps' / name)
        except PackageNotFoundError:
            pass
    except ImportError:  # running from the source tree without ROS
        pass
    found.append(_SOURCE_TREE / package / 'maps' / name)
    return found


def shipped_map(name: str = DEFAULT_MAP, package: str = PACKAGE) -> Path:
    """
    Return the path of a map shipped in ``package``'s ``maps/``: installed, else the source tree's.

    The path is returned even when no copy exists, so that loading it gives an error naming it.
    """
    candidates = _candidates(name, package)
    return next((p for p in candidates if p.is_file()), candidates[0])


def shipped_ceilings() -> Path:
    """Return where the shipped maps' ceilings are cached: installed, else the source tree."""
    candidates = _candidates(CEILINGS)
    return next((p for p in candidates if p.is_dir()), candidates[-1])
