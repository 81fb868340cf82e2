# Copyright 2026 Hexapod adaptation team
# All rights reserved.
#
# Permission is hereby granted, free of charge, to any person obtaining a copy
# of this software and associated documentation files (the "Software"), to deal
# in the Software without restriction, including without limitation the rights
# to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
# copies of the Software, and to permit persons to whom the Software is
# furnished to do so, subject to the following conditions:
#
# The above copyright notice and this permission notice shall be included in all
# copies or substantial portions of the Software.
#
# THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
# IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
# FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
# AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
# LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
# OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
# SOFTWARE.
"""
The middleware settings the hexapod's nodes run with.

``config/fastdds.xml`` lets a service wait up to 2 s (Fast DDS's default: 100 ms) for a new
client to be discovered before it answers, so that a first call from a base station, or any call
on a loaded machine, gets its answer (the file says why). Fast DDS reads it from the environment
variable :data:`PROFILES_ENV`; every node sets it at start through :func:`profile_environment`
(``hexapod_gait.ros_glue.run_node``) and ``scripts/env.sh`` exports it, never over a profile the
user chose.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from hexapod_description.model import share_path

# The variable Jazzy's Fast DDS 2.14 reads (it ignores FASTDDS_DEFAULT_PROFILES_FILE: measured).
PROFILES_ENV = 'FASTRTPS_DEFAULT_PROFILES_FILE'


def fastdds_profile_path() -> Path:
    """Path of the hexapod's Fast DDS profile file (installed share directory or source tree)."""
    return share_path('config', 'fastdds.xml')


def profile_environment(environ: Mapping[str, str]) -> dict[str, str]:
    """
    Return the variables to add to ``environ`` so that nodes started with it use the profile.

    Empty when ``environ`` already names a profile file: the user's choice stands.
    """
    if environ.get(PROFILES_ENV):
        return {}
    return {PROFILES_ENV: str(fastdds_profile_path())}
