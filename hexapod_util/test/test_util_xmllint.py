# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""ament_xmllint over this package's XML files (docs/lint.md: what runs offline)."""

import importlib.util
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1]
LINT = PACKAGE.parent / 'scripts' / 'package_lint.py'


@pytest.mark.linter
@pytest.mark.xmllint
def test_xmllint():
    spec = importlib.util.spec_from_file_location('package_lint', LINT)
    lint = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(lint)
    assert lint.xml_files(PACKAGE), 'no package.xml found'
    problems = lint.xmllint_problems(PACKAGE)
    assert not problems, '\n'.join(problems)
