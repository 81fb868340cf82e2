# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The xmllint step every package's lint test runs: offline, and it finds what is wrong."""

from __future__ import annotations

import importlib.util
from pathlib import Path
import shutil

import pytest

WS = Path(__file__).resolve().parents[2]
pytestmark = [pytest.mark.linter, pytest.mark.xmllint]
MANIFEST = """<?xml version="1.0"?>
<?xml-model href="http://download.ros.org/schema/package_format3.xsd" schematypens="http://www.w3.org/2001/XMLSchema"?>
<package format="3">
  <name>demo_pkg</name>
  <version>0.1.0</version>
  <description>A package for the test.</description>
  <maintainer email="a@b.org">Someone</maintainer>
  {license}
  <export><build_type>ament_python</build_type></export>
</package>
"""


def _package_lint():
    spec = importlib.util.spec_from_file_location(
        'package_lint', WS / 'scripts' / 'package_lint.py'
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.skipif(shutil.which('xmllint') is None, reason='needs libxml2-utils')
def test_manifests_are_checked_offline_and_a_bad_one_is_named(tmp_path, monkeypatch):
    import socket

    def no_network(*args, **kwargs):
        raise AssertionError('the lint step reached for the network')

    monkeypatch.setattr(socket, 'create_connection', no_network)
    monkeypatch.setattr(socket.socket, 'connect', no_network)
    lint = _package_lint()
    good = tmp_path / 'good'
    good.mkdir()
    (good / 'package.xml').write_text(MANIFEST.format(license='<license>MIT</license>'))
    assert lint.xmllint_problems(good) == []
    bad = tmp_path / 'bad'
    bad.mkdir()
    (bad / 'package.xml').write_text(MANIFEST.format(license=''))  # REP 149: a license is due
    problems = lint.xmllint_problems(bad)
    assert any('package.xml' in p and 'license' in p for p in problems), problems
    broken = tmp_path / 'broken'
    broken.mkdir()
    (broken / 'package.xml').write_text(MANIFEST.format(license='<license>MIT'))
    assert lint.xmllint_problems(broken), 'a file that is not well-formed passed'
