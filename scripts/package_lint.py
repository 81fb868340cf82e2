# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The package lint tests' shared steps (each package's test/test_<pkg>_{copyright,xmllint}.py).

package.xml's xml-model schema lives on a web host, and a test never reaches the network: the
manifests are validated offline by catkin_pkg's format-3 parser instead, the same check on every
machine (docs/lint.md).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path
import shutil
import subprocess


def _copyright_check():
    path = Path(__file__).with_name('copyright_check.py')
    spec = importlib.util.spec_from_file_location('copyright_check', path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def copyright_problems(package: Path) -> list[str]:
    """Check the package's SPDX copyright headers (copyright_check.py: why not ament's)."""
    return _copyright_check().check_package(package)


def xml_files(package: Path) -> list[Path]:
    """Return the package's XML files: manifest, URDF, xacro (test fixtures excluded)."""
    found = [p for s in ('*.xml', '*.urdf', '*.xacro') for p in package.rglob(s)]
    return sorted(p for p in found if 'test' not in p.relative_to(package).parts)


def xmllint_problems(package: Path) -> list[str]:
    """
    Check the package's XML files offline.

    Every file must be well-formed (``xmllint --nonet``); the files without a schema reference
    (the URDF, the xacro) go through ament_xmllint in full, and ``package.xml`` through
    catkin_pkg's format-3 parser, which holds it to REP 149 (what the schema checks).
    """
    from ament_xmllint.main import main
    from catkin_pkg.package import InvalidPackage, parse_package

    if shutil.which('xmllint') is None:
        return ['xmllint not found: install libxml2-utils (scripts/bootstrap.sh does)']
    files = [str(p) for p in xml_files(package)]
    problems = []
    for f in files:
        result = subprocess.run(['xmllint', '--noout', '--nonet', f], capture_output=True)
        if result.returncode != 0:
            problems.append(result.stderr.decode())
    schema_free = [f for f in files if 'xml-model' not in Path(f).read_text()]
    if schema_free and main(argv=schema_free) != 0:
        problems.append('ament_xmllint: see the output above')
    try:
        manifest = parse_package(str(package / 'package.xml'))
    except InvalidPackage as exc:
        return [*problems, f'package.xml: {exc}']
    if manifest.package_format != 3:
        problems.append(f'package.xml: format {manifest.package_format}, expected 3')
    return problems
