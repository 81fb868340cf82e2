# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A node's start-up loads none of the map-making or plotting libraries.

pyribs alone (with the scikit-learn, pandas and numba it imports) took 5 of adapt_node's 7 s of
imports on a busy 2-core machine; every `ros2 run`, every launch and every graph test paid it.
Each node and client is imported by its console script's module in a fresh interpreter, and the
modules it loaded are compared with the libraries only the offline tools need.
"""

from __future__ import annotations

import ast
from pathlib import Path
import subprocess
import sys

import pytest

WS = Path(__file__).resolve().parents[2]
#: Libraries the offline tools use (map making, plots, clusters); never a node's.
OFFLINE_ONLY = ('ribs', 'sklearn', 'pandas', 'numba', 'matplotlib', 'dask', 'distributed')


def node_modules() -> dict[str, str]:
    """Return {executable: module} of every package's nodes and clients (setup.py)."""
    found = {}
    for setup in sorted(WS.glob('hexapod_*/setup.py')):
        for node in ast.walk(ast.parse(setup.read_text(encoding='utf-8'))):
            text = node.value if isinstance(node, ast.Constant) else None
            if isinstance(text, str) and '=' in text:
                exe, _, target = (part.strip() for part in text.partition('='))
                if exe.endswith(('_node', '_client', 'state_publisher')) and ':' in target:
                    found[exe] = target.split(':')[0]
    return found


def test_the_nodes_are_found():
    names = set(node_modules())
    assert {'adapt_node', 'sim_node', 'gait_node', 'bridge_node', 'navigate_node'} <= names
    assert {'adapt_client', 'navigate_client', 'state_publisher'} <= names


@pytest.mark.parametrize('exe', sorted(node_modules()))
def test_a_node_loads_no_offline_library(exe):
    module = node_modules()[exe]
    probe = (
        f'import sys, {module}\nprint(" ".join(m for m in {OFFLINE_ONLY!r} if m in sys.modules))\n'
    )
    out = subprocess.run(
        [sys.executable, '-c', probe], capture_output=True, text=True, timeout=120, check=True
    )
    assert out.stdout.split() == [], f'{exe} ({module}) loads {out.stdout.strip()}'
