# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The scripts behind make: make_*.sh write where files ship; bench.py imports what exists."""

from __future__ import annotations

import importlib.util
from pathlib import Path
import re
import subprocess
import sys

import pytest

WS = Path(__file__).resolve().parents[2]


def _scripts() -> list[Path]:
    out = subprocess.run(
        ['git', 'ls-files', '*make_*.sh', ':!studies'],
        cwd=WS,
        capture_output=True,
        text=True,
        check=True,
    )
    return [WS / line for line in out.stdout.split()]


def test_every_make_script_writes_into_its_own_folder_and_names_itself():
    """After the package split two scripts wrote to hexapod_adapt/maps, not where files ship."""
    scripts = _scripts()
    assert len(scripts) >= 5
    for script in scripts:
        text = script.read_text()
        own = script.parent.relative_to(WS).as_posix()
        targets = re.findall(r'--(?:out|cache-dir) (\S+)', text)
        assert targets, f'{script.name} names no output'
        for target in targets:
            assert Path(target).parent.as_posix() == own or target == own, (script, target)
            assert (WS / target).exists(), f'{script.name} writes {target}, which is not shipped'
        for usage in re.findall(r'bash (\S+make_\S+\.sh)', text):
            assert usage == script.relative_to(WS).as_posix(), (script, usage)


def test_every_shell_script_parses():
    """A script run once a session (resume_default_map.sh ...) must not fail on its syntax."""
    out = subprocess.run(
        ['git', 'ls-files', '*.sh'], cwd=WS, capture_output=True, text=True, check=True
    )
    scripts = out.stdout.split()
    assert len(scripts) >= 10
    for script in scripts:
        r = subprocess.run(['bash', '-n', script], cwd=WS, capture_output=True, text=True)
        assert r.returncode == 0, f'{script}: {r.stderr}'


@pytest.mark.parametrize('script', ['bench.py', 'bench_adapt.py'])
def test_every_name_the_benchmarks_import_exists(script: str):
    """The benchmarks import per area, when they run: a name moved by a refactor broke one."""
    import ast
    import importlib

    tree = ast.parse((WS / 'scripts' / script).read_text())
    missing = []
    for node in ast.walk(tree):
        if not (isinstance(node, ast.ImportFrom) and node.module):
            continue
        if not node.module.startswith(('hexapod_', 'studies')):
            continue
        module = importlib.import_module(node.module)
        for alias in node.names:
            if hasattr(module, alias.name):
                continue
            try:  # a submodule: from package import module
                importlib.import_module(f'{node.module}.{alias.name}')
            except ImportError:
                missing.append(f'{node.module}.{alias.name}')
    assert not missing, f'scripts/{script} imports names that do not exist: {missing}'


def _collected(*args: str) -> list[str]:
    out = subprocess.run(
        [sys.executable, '-m', 'pytest', '--collect-only', '-q', *args],
        cwd=WS,
        capture_output=True,
        text=True,
        timeout=300,
    )
    return [line for line in out.stdout.splitlines() if '::' in line]


def test_make_tests_two_processes_run_every_test_once():
    """run_tests.py's selections split the tests: none left out, none run twice."""
    spec = importlib.util.spec_from_file_location('run_tests', WS / 'scripts' / 'run_tests.py')
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    paths = ['tests/graph', 'hexapod_util/test']  # graph tests of both lanes, and others
    everything = _collected(*paths)
    parts = [_collected('-m', selection, *paths) for _, selection in module.PARTS]
    assert all(parts) and sorted(sum(parts, [])) == sorted(everything)
    second = [t for t in parts[1] if t.startswith('tests/graph/')]
    assert second and len(second) < len([t for t in parts[0] if t.startswith('tests/graph/')])
