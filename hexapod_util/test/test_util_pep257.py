# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""ament_pep257 over this package, with its 'ament' convention (the ROS 2 docstring style)."""

from pathlib import Path

from ament_pep257.main import main
import pytest

PACKAGE = Path(__file__).resolve().parents[1]


@pytest.mark.linter
@pytest.mark.pep257
def test_pep257():
    assert main(argv=[str(PACKAGE)]) == 0, 'docstring style findings: see the output above'
