# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Fixtures of the navigation tests: the shipped repertoire, a MuJoCo simulator."""

from hexapod_adapt import load_archive
from hexapod_navigation.core.repertoire import Repertoire, shipped_repertoire
from hexapod_sim import create_simulator, SimConfig
import pytest

REPERTOIRE = shipped_repertoire()


@pytest.fixture(scope='module')
def repertoire():
    return Repertoire.from_archive(load_archive(REPERTOIRE))


@pytest.fixture
def sim():
    with create_simulator(SimConfig(engine='mujoco')) as s:
        yield s
