# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""`make demo` and `make demo-navigate` run end to end: the README's first commands work."""

from __future__ import annotations

import os
from pathlib import Path
import subprocess
import sys

from hexapod_util.recording import read_messages
import pytest

WS = Path(__file__).resolve().parents[2]


def _run_demo(script: str, out: Path, timeout: float) -> subprocess.CompletedProcess:
    """Run scripts/SCRIPT --out OUT on this machine's loopback only; return what it did."""
    env = dict(os.environ, ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST')
    return subprocess.run(
        [sys.executable, str(WS / 'scripts' / script), '--out', str(out)],
        env=env, capture_output=True, text=True, timeout=timeout,
    )  # fmt: skip


@pytest.mark.slow
def test_the_demo_adapts_through_the_graph_and_records_a_replayable_run(tmp_path):
    done = _run_demo('demo.py', tmp_path, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    assert 'adapted gait' in done.stdout, done.stdout
    (recording,) = (tmp_path / 'runs').glob('*.mcap')
    topics = [topic for topic, _, _ in read_messages(recording)]
    # the run starts with what Foxglove's 3D panel needs, then the trials
    assert set(topics[:2]) == {'/robot_description', '/tf_static'}, topics[:5]
    assert topics.count('/adapt/trials') >= 1


@pytest.mark.slow
def test_the_navigation_demo_reaches_its_three_goals_and_records_each(tmp_path):
    """`make demo-navigate` (scripts/demo_navigate.py): the README's navigation demo works."""
    done = _run_demo('demo_navigate.py', tmp_path, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    ended = [line for line in done.stdout.splitlines() if line.startswith('goal (')]
    assert len(ended) == 3, done.stdout
    recordings = sorted((tmp_path / 'runs').glob('*.mcap'))
    assert len(recordings) == 3
    for recording in recordings:
        topics = {topic for topic, _, _ in read_messages(recording)}
        assert {'/navigate/goal', '/odom', '/robot_description', '/tf_static'} <= topics
