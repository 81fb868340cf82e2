# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Copyright headers: a Copyright line and the SPDX licence id (scripts/copyright_check.py)."""

import importlib.util
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1]
LINT = PACKAGE.parent / 'scripts' / 'package_lint.py'


@pytest.mark.copyright
@pytest.mark.linter
def test_copyright():
    spec = importlib.util.spec_from_file_location('package_lint', LINT)
    lint = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(lint)
    problems = lint.copyright_problems(PACKAGE)
    assert not problems, '\n'.join(problems)
