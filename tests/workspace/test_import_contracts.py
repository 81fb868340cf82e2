# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The import contracts (.importlinter) hold, and they catch a violation.

DESIGN.md's layers (description < gait < sim < adapt < navigation; the bridge above sim and
independent of adapt and navigation), no module importing a node, rclpy only in nodes and ROS
glue, no study (studies/) imported by the library, and no import cycle in any package.
"""

from __future__ import annotations

import os
from pathlib import Path
import shutil
import subprocess

import pytest

WS = Path(__file__).resolve().parents[2]


def lint_imports(pythonpath: str | None = None) -> subprocess.CompletedProcess:
    """Run import-linter over the workspace's contracts; its output and status."""
    env = dict(os.environ)
    if pythonpath is not None:
        env['PYTHONPATH'] = pythonpath
    return subprocess.run(
        ['lint-imports', '--config', str(WS / '.importlinter'), '--no-cache', '--no-logo'],
        cwd=WS,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )


@pytest.mark.linter
def test_the_import_contracts_are_kept():
    run = lint_imports()
    assert run.returncode == 0, run.stdout + run.stderr
    assert 'Contracts: 9 kept, 0 broken.' in run.stdout, run.stdout


def _copy_with(tmp_path: Path, package: str, module: str, line: str) -> str:
    """A copy of package whose module also runs line; PYTHONPATH putting it first."""
    src = Path(__import__(package).__file__).resolve().parent
    dst = tmp_path / package
    shutil.copytree(src, dst, ignore=shutil.ignore_patterns('__pycache__'))
    path = dst / f'{module}.py'
    path.write_text(path.read_text() + f'\n{line}  # noqa\n')
    return os.pathsep.join([str(tmp_path), os.environ.get('PYTHONPATH', '')])


@pytest.mark.linter
@pytest.mark.parametrize(
    'package,module,line,broken',
    [
        ('hexapod_sim', 'damage', 'import hexapod_adapt', 'Layers'),
        ('hexapod_bridge', 'protocol/crc', 'import hexapod_navigation', 'independent'),
        ('hexapod_adapt', 'online/mboa', 'import studies.tuning_set', 'Layers'),
        ('hexapod_adapt', 'mapping/cvt', 'import hexapod_adapt.online.mboa', 'by job'),
        (
            'hexapod_navigation',
            'core/planner',
            'import hexapod_navigation.ros.navigate_node',
            'a node',
        ),
        (
            'hexapod_navigation',
            'core/planner',
            'import hexapod_navigation.offline.plots',
            'by job',
        ),
        ('hexapod_navigation', 'core/planner', 'import hexapod_adapt.online.mboa', 'public API'),
        ('hexapod_adapt', 'online/prior', 'import rclpy', 'rclpy only'),
        ('hexapod_gait', 'kinematics', 'import hexapod_gait.trajectory', 'cycle'),
    ],
)
def test_a_violation_breaks_its_contract(tmp_path, package, module, line, broken):
    run = lint_imports(_copy_with(tmp_path, package, module, line))
    assert run.returncode != 0, run.stdout
    broken_lines = run.stdout.split('Broken contracts')[-1]
    assert broken in broken_lines, run.stdout
