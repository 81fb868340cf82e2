# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The middleware settings the hexapod's nodes run with.

``config/fastdds.xml`` lets a service wait up to 2 s (Fast DDS's default: 100 ms) for a new
client to be discovered before it answers, so that a first call from a base station, or any call
on a loaded machine, gets its answer (the file says why). Fast DDS reads it from the environment
variable :data:`PROFILES_ENV`; every node sets it at start through :func:`profile_environment`
(``hexapod_util.ros_glue.run_node``) and ``scripts/env.sh`` exports it, never over a profile the
user chose.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

# The variable Jazzy's Fast DDS 2.14 reads (it ignores FASTDDS_DEFAULT_PROFILES_FILE: measured).
PROFILES_ENV = 'FASTRTPS_DEFAULT_PROFILES_FILE'


def fastdds_profile_path() -> Path:
    """Path of the hexapod's Fast DDS profile file (installed share directory or source tree)."""
    try:
        from ament_index_python.packages import get_package_share_directory, PackageNotFoundError

        try:
            installed = Path(get_package_share_directory('hexapod_util'), 'config', 'fastdds.xml')
            if installed.is_file():
                return installed
        except (PackageNotFoundError, OSError):  # OSError: no AMENT_PREFIX_PATH at all
            pass
    except ImportError:  # plain Python without the ROS wheels
        pass
    return Path(__file__).resolve().parent.parent / 'config' / 'fastdds.xml'


def profile_environment(environ: Mapping[str, str]) -> dict[str, str]:
    """
    Return the variables to add to ``environ`` so that nodes started with it use the profile.

    Empty when ``environ`` already names a profile file: the user's choice stands.
    """
    if environ.get(PROFILES_ENV):
        return {}
    return {PROFILES_ENV: str(fastdds_profile_path())}
