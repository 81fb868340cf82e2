# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Lint of the interface package under pytest: copyright headers and xmllint.

On a full ROS 2 install ament_lint_auto runs ament_lint_common's tests from CMakeLists.txt
as well (it has no PyPI wheel). The .msg and .srv files are checked by rosidl at build time.
"""

import importlib.util
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1]
LINT = PACKAGE.parent / 'scripts' / 'package_lint.py'


def _lint():
    spec = importlib.util.spec_from_file_location('package_lint', LINT)
    lint = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(lint)
    return lint


@pytest.mark.copyright
@pytest.mark.linter
def test_copyright():
    problems = _lint().copyright_problems(PACKAGE)
    assert not problems, '\n'.join(problems)


@pytest.mark.linter
@pytest.mark.xmllint
def test_xmllint():
    problems = _lint().xmllint_problems(PACKAGE)
    assert not problems, '\n'.join(problems)
