# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The sizes the layout agreed on hold: every node ≤ 330 lines, no library function over 80 lines.

A node is a thin shell over the library (DESIGN.md); a function that needs more than 80 lines
(its docstring and an argument parser built from a table count) is doing several things.
"""

from __future__ import annotations

import ast
from pathlib import Path

WS = Path(__file__).resolve().parents[2]
MAX_NODE_LINES = 330
MAX_FUNCTION_LINES = 80


def product_modules() -> list[Path]:
    """Return the packages' Python modules (hexapod_*/hexapod_*/**), tests and studies aside."""
    return sorted(p for p in WS.glob('hexapod_*/hexapod_*/**/*.py'))


def long_functions(path: Path, limit: int) -> list[str]:
    """Return 'line name (n lines)' for each function in ``path`` over ``limit`` lines."""
    tree = ast.parse(path.read_text(encoding='utf-8'))
    return [
        f'{n.lineno} {n.name} ({n.end_lineno - n.lineno + 1} lines)'
        for n in ast.walk(tree)
        if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))
        and n.end_lineno - n.lineno + 1 > limit
    ]


def test_no_product_function_is_over_80_lines():
    modules = product_modules()
    assert len(modules) > 50  # the glob found the packages
    over = {
        str(p.relative_to(WS)): found
        for p in modules
        if (found := long_functions(p, MAX_FUNCTION_LINES))
    }
    assert not over, over


def test_every_node_is_at_most_330_lines():
    nodes = [p for p in product_modules() if p.name.endswith('_node.py')]
    assert len(nodes) >= 6
    sizes = {
        str(p.relative_to(WS)): len(p.read_text(encoding='utf-8').splitlines()) for p in nodes
    }
    assert all(n <= MAX_NODE_LINES for n in sizes.values()), sizes


def test_the_check_finds_a_long_function(tmp_path):
    body = '\n'.join(f'    x{i} = {i}' for i in range(85))
    probe = tmp_path / 'probe.py'
    probe.write_text(f'def long():\n{body}\n\n\ndef short():\n    return 1\n', encoding='utf-8')
    assert long_functions(probe, MAX_FUNCTION_LINES) == ['1 long (86 lines)']
