# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Every node's logger is guarded against its context's shutdown (hexapod_util.guarded_logging)."""

from __future__ import annotations

import subprocess
import sys

import pytest
from test_node_startup import node_modules

#: Prints the node classes a module defines that do not take GuardedLogging.
PROBE = """
import importlib, inspect
from rclpy.node import Node
from hexapod_util.guarded_logging import GuardedLogging
module = importlib.import_module({module!r})
nodes = [c for _, c in inspect.getmembers(module, inspect.isclass)
         if issubclass(c, Node) and c.__module__ == module.__name__]
print(len(nodes), ' '.join(c.__name__ for c in nodes if not issubclass(c, GuardedLogging)))
"""


@pytest.mark.parametrize('exe', sorted(e for e in node_modules() if not e.endswith('_client')))
def test_a_node_class_takes_guarded_logging(exe):
    module = node_modules()[exe]
    out = subprocess.run(
        [sys.executable, '-c', PROBE.format(module=module)],
        capture_output=True,
        text=True,
        timeout=120,
        check=True,
    )
    count, *unguarded = out.stdout.split()
    assert int(count) >= 1, f'{exe}: no node class found in {module}'
    assert unguarded == [], f'{exe} ({module}): {unguarded} log without the shutdown guard'
