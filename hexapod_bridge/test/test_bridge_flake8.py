# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""ament_flake8 over this package, with ament_flake8's own configuration (the ROS 2 style)."""

from pathlib import Path

from ament_flake8.main import main_with_errors
import pytest

PACKAGE = Path(__file__).resolve().parents[1]


@pytest.mark.slow
@pytest.mark.flake8
@pytest.mark.linter
def test_flake8():
    rc, errors = main_with_errors(argv=[str(PACKAGE)])
    assert rc == 0, f'{len(errors)} flake8 findings (make format fixes most):\n' + '\n'.join(
        errors
    )
