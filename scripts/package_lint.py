# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The package lint tests' shared steps (each package's test/test_<pkg>_{copyright,xmllint}.py).

The xmllint schema needs a host this environment may not reach (docs/lint.md): the logic for
choosing a stand-in lives here once instead of in every package's test.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path
import shutil
import socket
import subprocess

SCHEMA_HOST = 'download.ros.org'  # package.xml's xml-model schema lives there


def _copyright_check():
    path = Path(__file__).with_name('copyright_check.py')
    spec = importlib.util.spec_from_file_location('copyright_check', path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def copyright_problems(package: Path) -> list[str]:
    """Check the package's SPDX copyright headers (copyright_check.py: why not ament's)."""
    return _copyright_check().check_package(package)


def _schema_reachable() -> bool:
    try:
        socket.create_connection((SCHEMA_HOST, 80), timeout=3).close()
    except OSError:
        return False
    return True


def xml_files(package: Path) -> list[Path]:
    """Return the package's XML files: manifest, URDF, xacro (test fixtures excluded)."""
    found = [p for s in ('*.xml', '*.urdf', '*.xacro') for p in package.rglob(s)]
    return sorted(p for p in found if 'test' not in p.relative_to(package).parts)


def xmllint_problems(package: Path) -> list[str]:
    """
    Run ament_xmllint on the package's XML files.

    Offline, xmllint cannot fetch package.xml's schema: then every file is checked to be
    well-formed, the files without a schema reference fully, and tests/workspace/test_manifests.py
    checks the manifests' content with catkin_pkg.
    """
    from ament_xmllint.main import main

    if shutil.which('xmllint') is None:
        return ['xmllint not found: install libxml2-utils (scripts/bootstrap.sh does)']
    files = [str(p) for p in xml_files(package)]
    if _schema_reachable():
        return [] if main(argv=files) == 0 else ['ament_xmllint: see the output above']
    problems = []
    for f in files:
        result = subprocess.run(['xmllint', '--noout', '--nonet', f], capture_output=True)
        if result.returncode != 0:
            problems.append(result.stderr.decode())
    schema_free = [f for f in files if 'xml-model' not in Path(f).read_text()]
    if schema_free and main(argv=schema_free) != 0:
        problems.append('ament_xmllint: see the output above')
    return problems
