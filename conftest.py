# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Every test process's home is a temporary directory of its own; ROS graphs run one at a time.

Nodes and commands write under HOME (the damage-informed prior's cache in ~/.cache, ROS logs and
recordings under ~/.ros, matplotlib's cache): a test must neither leave files there nor read
what an earlier run left, so each pytest process (each xdist worker too) gets a fresh HOME,
removed at its end.

Every test that starts a ROS graph or a node is marked ``graph``: ``make test`` runs those one at
a time in one pytest process and the rest in another beside it (scripts/run_tests.py). Two
graphs beside each other on a 2-core machine starved each other's timers and emulated robots
(2026-12-02), and some use fixed paths (the launcher's /tmp/hexapod_radio).
"""

from __future__ import annotations

import os
from pathlib import Path
import shutil
import tempfile

import pytest

_HOME: dict[str, str] = {}
#: what lives under HOME, each pointed into the temporary one
_UNDER_HOME = (('XDG_CACHE_HOME', '.cache'), ('ROS_HOME', '.ros'), ('MPLCONFIGDIR', '.mpl'))


def pytest_configure(config) -> None:
    home = tempfile.mkdtemp(prefix='hexapod-test-home-')
    _HOME['path'] = home
    for name, sub in _UNDER_HOME:
        Path(home, sub).mkdir()
        os.environ[name] = str(Path(home, sub))
    os.environ['HOME'] = home


def pytest_unconfigure(config) -> None:
    shutil.rmtree(_HOME.pop('path', ''), ignore_errors=True)


#: What marks a test that starts a ROS graph or node: its mark, its fixtures, its folder.
GRAPH_FIXTURES = {'ros', 'launch', 'domain_id', 'env'}
GRAPH_FILES = ('tests/graph/', 'tests/workspace/test_demo.py', 'tests/workspace/test_launch.py')
#: Graph tests (files or test ids) `make test` runs in the other process, after the packages'
#: tests: the robot path's 20 faulted runs and its cancel on a dead link (about 5 of the graph
#: tests' minutes here), so the two halves end together (a fresh clone at f0e34d5 here: graph
#: lane 35 min, library lane 44, with the dead-servo and port tests, 3.6 min, in the library's).
SECOND_LANE = (
    'tests/graph/test_robot_faults_graph.py::test_faults_in_the_middle_of_robot_trials',
    'tests/graph/test_robot_faults_graph.py::test_a_cancel_while_the_link_is_down',
)


@pytest.hookimpl(tryfirst=True)  # before -m selects by it
def pytest_collection_modifyitems(config, items) -> None:
    for item in items:
        path = item.nodeid.split('::', 1)[0]
        fixtures = set(getattr(item, 'fixturenames', ()))
        if (
            item.get_closest_marker('ros') is not None
            or fixtures & GRAPH_FIXTURES
            or path.startswith(GRAPH_FILES)
        ):
            item.add_marker(pytest.mark.graph)
            if item.nodeid.startswith(SECOND_LANE):
                item.add_marker(pytest.mark.second_lane)
