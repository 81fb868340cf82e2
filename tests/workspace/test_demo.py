# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""`make demo` (scripts/demo.py) runs end to end: the README's first command works."""

from __future__ import annotations

import os
from pathlib import Path
import subprocess
import sys

from hexapod_util.recording import read_messages

WS = Path(__file__).resolve().parents[2]


def test_the_demo_adapts_through_the_graph_and_records_a_replayable_run(tmp_path):
    env = dict(os.environ, ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST')
    done = subprocess.run(
        [sys.executable, str(WS / 'scripts' / 'demo.py'), '--out', str(tmp_path)],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert 'adapted gait' in done.stdout, done.stdout
    (recording,) = (tmp_path / 'runs').glob('*.mcap')
    topics = [topic for topic, _, _ in read_messages(recording)]
    # the run starts with what Foxglove's 3D panel needs, then the trials
    assert set(topics[:2]) == {'/robot_description', '/tf_static'}, topics[:5]
    assert topics.count('/adapt/trials') >= 1
