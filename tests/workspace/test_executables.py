# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Every declared executable is installed where `ros2 run` looks, and its entry point imports."""

from __future__ import annotations

import ast
import importlib
import os
from pathlib import Path
import subprocess

from ament_index_python.packages import get_package_prefix
import pytest

WS = Path(__file__).resolve().parents[2]
PACKAGES = [
    'hexapod_description',
    'hexapod_gait',
    'hexapod_sim',
    'hexapod_adapt',
    'hexapod_navigation',
    'hexapod_bridge',
]


def console_scripts(pkg: str) -> list[tuple[str, str]]:
    """(executable, 'module:function') pairs declared in the package's setup.py."""
    tree = ast.parse((WS / pkg / 'setup.py').read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.Dict):
            for key, value in zip(node.keys, node.values):
                if isinstance(key, ast.Constant) and key.value == 'console_scripts':
                    entries = ast.literal_eval(value)
                    return [tuple(s.strip() for s in e.split('=', 1)) for e in entries]
    return []


DECLARED = [(pkg, exe, target) for pkg in PACKAGES for exe, target in console_scripts(pkg)]


def test_packages_declare_their_executables():
    names = {(pkg, exe) for pkg, exe, _ in DECLARED}
    assert {('hexapod_gait', 'gait_node'), ('hexapod_description', 'describe')} <= names


@pytest.mark.parametrize('pkg,exe,target', DECLARED, ids=[f'{p}/{e}' for p, e, _ in DECLARED])
def test_executable_found_like_ros2_run(pkg, exe, target):
    # ros2 run: prefix from the ament index, then <prefix>/lib/<pkg>/<exe>, must be executable
    prefix = Path(get_package_prefix(pkg))
    assert prefix == WS / 'install' / pkg
    path = prefix / 'lib' / pkg / exe
    assert path.is_file(), f'{path} missing'
    assert os.access(path, os.X_OK), f'{path} not executable'
    module, func = target.split(':')
    assert callable(getattr(importlib.import_module(module), func))


def test_every_package_is_in_the_ament_index():
    for pkg in PACKAGES + ['hexapod_msgs']:
        assert (Path(get_package_prefix(pkg)) / 'share' / pkg / 'package.xml').is_file()


@pytest.mark.parametrize(
    'pkg,exe,module',
    [
        ('hexapod_sim', 'sim_node', 'hexapod_sim.sim_node'),
        ('hexapod_gait', 'gait_node', 'hexapod_gait.gait_node'),
        ('hexapod_bridge', 'bridge_node', 'hexapod_bridge.bridge_node'),
        ('hexapod_adapt', 'adapt_node', 'hexapod_adapt.ros.adapt_node'),
    ],
)
def test_node_executables_answer_help_with_their_parameters(pkg, exe, module):
    specs = importlib.import_module(module).PARAMETERS
    result = subprocess.run(
        [str(WS / 'install' / pkg / 'lib' / pkg / exe), '--help'],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith(f'usage: {exe}')
    for spec in specs:
        assert f'  {spec.name} (' in result.stdout and spec.description[:30] in result.stdout


CLI_MODULES = sorted(
    '.'.join(path.relative_to(WS / pkg).with_suffix('').parts)
    for pkg in PACKAGES
    for path in (WS / pkg / pkg).rglob('*_cli.py')
)


def test_every_package_has_command_line_tools_to_check():
    assert 'hexapod_adapt.online.ceilings_cli' in CLI_MODULES and len(CLI_MODULES) >= 15


@pytest.mark.parametrize('module', CLI_MODULES)
def test_every_command_line_tool_answers_help(module, monkeypatch, capsys):
    # argparse formats each option's help with %: a bare % in a help text crashes --help
    monkeypatch.setattr('sys.argv', [module.rsplit('.', 1)[1], '--help'])
    with pytest.raises(SystemExit) as stop:
        importlib.import_module(module).main()
    assert stop.value.code == 0
    assert capsys.readouterr().out.startswith('usage: ')
