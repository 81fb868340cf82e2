# Copyright 2026 Hexapod adaptation team
# All rights reserved.
#
# Permission is hereby granted, free of charge, to any person obtaining a copy
# of this software and associated documentation files (the "Software"), to deal
# in the Software without restriction, including without limitation the rights
# to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
# copies of the Software, and to permit persons to whom the Software is
# furnished to do so, subject to the following conditions:
#
# The above copyright notice and this permission notice shall be included in all
# copies or substantial portions of the Software.
#
# THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
# IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
# FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
# AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
# LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
# OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
# SOFTWARE.
"""`make demo` (scripts/demo.py) runs end to end: the README's first command works."""

from __future__ import annotations

import os
from pathlib import Path
import subprocess
import sys

from hexapod_adapt.ros.recording import read_messages

WS = Path(__file__).resolve().parent.parent


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
