#!/usr/bin/env python3
# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Repair the include paths baked into the ROS 2 Jazzy PyPI wheels' CMake exports.

Why: the ros-jazzy-* wheels were built in a manylinux container whose Python lived in
/opt/python/cp311-cp311. Their exported CMake targets (share/*/cmake/*.cmake) still name
that interpreter's include directory and its numpy include directory. Any rosidl package
(our hexapod_msgs) that links against those targets fails to configure until the paths
point at this virtual environment's real Python and numpy headers.

Idempotent: a file is rewritten only when it still contains the stale prefix; running it
again changes nothing. Usage: fix_ros_wheel_cmake.py <venv-prefix>
"""

from __future__ import annotations

import os
from pathlib import Path
import sys
import sysconfig

STALE_PYTHON_INCLUDE = '/opt/python/cp311-cp311/include/python3.11'
STALE_NUMPY_INCLUDE = '/opt/python/cp311-cp311/lib/python3.11/site-packages/numpy/_core/include'


def repair(prefix: Path) -> int:
    """Rewrite stale include paths under prefix/share/*/cmake; return files changed."""
    import numpy  # imported here so --help works without numpy

    python_include = sysconfig.get_paths()['include']
    numpy_include = numpy.get_include()
    for path in (python_include, numpy_include):
        if not os.path.isdir(path):
            raise SystemExit(f'fix_ros_wheel_cmake: include directory {path} does not exist')
    changed = 0
    for cmake_file in sorted(prefix.glob('share/*/cmake/*.cmake')):
        text = cmake_file.read_text()
        if STALE_PYTHON_INCLUDE not in text and STALE_NUMPY_INCLUDE not in text:
            continue
        # Numpy first: its stale path contains the stale Python prefix as a substring only
        # by directory, not by the include/python3.11 suffix, so order does not matter for
        # correctness, but keep it explicit.
        text = text.replace(STALE_NUMPY_INCLUDE, numpy_include)
        text = text.replace(STALE_PYTHON_INCLUDE, python_include)
        tmp = cmake_file.with_suffix(cmake_file.suffix + '.tmp')
        tmp.write_text(text)
        os.replace(tmp, cmake_file)
        changed += 1
    return changed


def main() -> None:
    if len(sys.argv) != 2 or sys.argv[1] in ('-h', '--help'):
        print(__doc__)
        raise SystemExit(0 if len(sys.argv) == 2 else 2)
    prefix = Path(sys.argv[1]).resolve()
    if not (prefix / 'share').is_dir():
        raise SystemExit(
            f'fix_ros_wheel_cmake: {prefix}/share not found; is {prefix} a venv with ROS wheels?'
        )
    n = repair(prefix)
    print(f'fix_ros_wheel_cmake: {n} CMake export file(s) repaired under {prefix}/share')


if __name__ == '__main__':
    main()
