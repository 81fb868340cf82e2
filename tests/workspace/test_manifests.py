# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Every import of every package is declared in its package.xml (so rosdep can install it).

And every package carries a LICENSE matching its manifest.
"""

from __future__ import annotations

import ast
from pathlib import Path
import re
import sys

import pytest

WS = Path(__file__).resolve().parents[2]
PACKAGES = [
    'hexapod_util',
    'hexapod_description',
    'hexapod_gait',
    'hexapod_sim',
    'hexapod_bridge',
    'hexapod_adapt',
    'hexapod_navigation',
]

#: Python module -> rosdep key. ROS packages are their own key. Keys ending in -pip are defined
#: in rosdep/hexapod.yaml (rosdep's database is not known to have them).
MODULE_KEYS = {
    'numpy': 'python3-numpy',
    'scipy': 'python3-scipy',
    'matplotlib': 'python3-matplotlib',
    'serial': 'python3-serial',
    'PIL': 'python3-pil',
    'sklearn': 'python3-sklearn',
    'pytest': 'python3-pytest',
    'tqdm': 'python3-tqdm',
    'hypothesis': 'python3-hypothesis',
    'yaml': 'python3-yaml',
    'pybullet': 'python3-pybullet-pip',
    'pybullet_data': 'python3-pybullet-pip',
    'mujoco': 'python3-mujoco-pip',
    'dartpy': 'python3-dartpy-pip',
    'mcap': 'python3-mcap-pip',
    'ribs': 'python3-ribs-pip',
    'mcap_ros2': 'python3-mcap-ros2-support-pip',
    'distributed': 'python3-distributed-pip',
    'yourdfpy': 'python3-yourdfpy-pip',
    'threadpoolctl': 'python3-threadpoolctl-pip',
    'zstandard': 'python3-zstandard-pip',
}
#: Imported only when a user asks for them (the error message says what to install).
OPTIONAL = {'mpi4py'}  # generate_map --backend mpi


def _imports(files: list[Path]) -> set[str]:
    found = set()
    for path in files:
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                found.update(alias.name.split('.')[0] for alias in node.names)
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                found.add(node.module.split('.')[0])
    return found - set(sys.stdlib_module_names) - {'__future__'}


def _declared(pkg: str, tags: tuple[str, ...]) -> set[str]:
    xml = (WS / pkg / 'package.xml').read_text()
    return {key for tag in tags for key in re.findall(rf'<{tag}>([^<]+)</{tag}>', xml)}


@pytest.mark.parametrize('pkg', PACKAGES)
def test_every_import_is_declared(pkg):
    root = WS / pkg
    run = (
        _imports(list((root / pkg).rglob('*.py')) + list((root / 'launch').glob('*.py')))
        - {pkg}
        - OPTIONAL
    )
    test = _imports(list((root / 'test').glob('*.py'))) - {pkg}
    run_keys = _declared(pkg, ('depend', 'exec_depend'))
    test_keys = run_keys | _declared(pkg, ('test_depend',))
    missing = sorted({MODULE_KEYS.get(m, m) for m in run} - run_keys)
    missing_test = sorted({MODULE_KEYS.get(m, m) for m in test} - test_keys)
    assert not missing, f'{pkg}/package.xml lacks exec_depend for {missing}'
    assert not missing_test, f'{pkg}/package.xml lacks test_depend for {missing_test}'


def test_every_pip_key_is_defined_in_the_workspace_rosdep_file():
    defined = set(re.findall(r'^(\S+):\s*$', (WS / 'rosdep' / 'hexapod.yaml').read_text(), re.M))
    used = {
        key for pkg in PACKAGES for key in _declared(pkg, ('depend', 'exec_depend', 'test_depend'))
    }
    assert {k for k in used if k.endswith('-pip')} <= defined


@pytest.mark.parametrize('pkg', PACKAGES + ['hexapod_msgs'])
def test_every_package_has_a_license_matching_its_manifest(pkg):
    license_tag = re.search(
        r'<license>([^<]+)</license>', (WS / pkg / 'package.xml').read_text()
    ).group(1)
    text = (WS / pkg / 'LICENSE').read_text()
    assert license_tag == 'MIT' and text.startswith('MIT License')
