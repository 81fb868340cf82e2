# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The shipped views (RViz 2, Foxglove) open ready.

They parse, and every topic and frame they show is one the graph has (published by a node of the
workspace; a frame of the URDF, or odom).
"""

from __future__ import annotations

import json
from pathlib import Path
import re

import pytest
import yaml

PKG = Path(__file__).resolve().parents[1]
WS = PKG.parent
#: The publishers the workspace's nodes create, found in their sources (topic names as written).
PUBLISHER = re.compile(r"create_publisher\(\s*[A-Za-z_.]+,\s*(?:'([^']+)'|([A-Z_]+)\b)")


def _published() -> set[str]:
    names = set()
    for source in WS.glob('hexapod_*/hexapod_*/**/*.py'):
        text = source.read_text()
        for literal, constant in PUBLISHER.findall(text):
            if constant:  # a module constant of the same file, e.g. TOPIC = '/diagnostics'
                found = re.search(rf"^{constant}\s*=\s*'([^']+)'", text, re.M)
                literal = found.group(1) if found else ''
            if literal:
                names.add('/' + literal.lstrip('/'))
    return names


def _frames() -> set[str]:
    urdf = (PKG / 'urdf' / 'hexapod.urdf').read_text()
    return set(re.findall(r'<link name="([^"]+)"', urdf)) | {'odom'}


def test_the_workspace_publishes_the_topics_it_is_checked_against():
    published = _published()
    assert {'/robot_description', '/odom', '/adapt/trials', '/navigate/goal'} <= published
    assert '/diagnostics' in published  # hexapod_util.diagnostics


def _rviz_topics(node) -> list[str]:
    found = []
    if isinstance(node, dict):
        for key, value in node.items():
            if key.endswith('Topic') and isinstance(value, dict):
                found.append(value['Value'])
            else:
                found += _rviz_topics(value)
    elif isinstance(node, list):
        for value in node:
            found += _rviz_topics(value)
    return found


def test_the_rviz_config_shows_what_the_graph_publishes():
    config = yaml.safe_load((PKG / 'rviz' / 'hexapod.rviz').read_text())
    manager = config['Visualization Manager']
    assert manager['Global Options']['Fixed Frame'] in _frames()
    assert manager['Views']['Current']['Target Frame'] in _frames()
    classes = {d['Class'] for d in manager['Displays']}
    assert {'rviz_default_plugins/RobotModel', 'rviz_default_plugins/TF'} <= classes
    topics = _rviz_topics(manager['Displays'])
    assert '/robot_description' in topics and '/odom' in topics
    assert set(topics) <= _published(), set(topics) - _published()


def _panels(tree) -> list[str]:
    if isinstance(tree, str):
        return [tree]
    return _panels(tree['first']) + _panels(tree['second'])


def test_the_foxglove_layout_shows_what_the_graph_publishes():
    layout = json.loads((PKG / 'foxglove' / 'hexapod.json').read_text())
    panels = _panels(layout['layout'])
    assert sorted(panels) == sorted(layout['configById']), 'every panel laid out, and only those'
    kinds = {p.split('!')[0] for p in panels}
    assert {'3D', 'DiagnosticSummary', 'Plot'} <= kinds
    configs = layout['configById']
    assert configs['3D!hexapod']['followTf'] in _frames()
    topics = set(configs['3D!hexapod']['topics'])
    topics |= {configs[p]['topicToRender'] for p in panels if p.startswith('DiagnosticSummary')}
    topics |= {configs[p]['topicPath'] for p in panels if p.startswith('RawMessages')}
    for p in (p for p in panels if p.startswith('Plot')):
        topics |= {path['value'].split('.')[0] for path in configs[p]['paths']}
    assert '/diagnostics' in topics and '/robot_description' in topics
    assert topics <= _published(), topics - _published()


@pytest.mark.parametrize('view', ['rviz/hexapod.rviz', 'foxglove/hexapod.json'])
def test_the_views_are_installed(view: str):
    setup = (PKG / 'setup.py').read_text()
    folder, name = view.split('/')
    assert f"glob('{folder}/*.{name.split('.')[-1]}')" in setup
