# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Run every test in two pytest processes side by side: `make test`.

One process runs the tests that start a ROS graph or a node (marked ``graph`` by conftest.py),
one at a time; the other runs the rest, the graph tests marked ``second_lane`` among them (the
robot path's real-time trials, collected after the packages' tests), so that the two end
together. So the 2-core machine's second
core works while the graphs wait on DDS and simulated time. Each process takes its own DDS
domains (``HEXAPOD_TEST_SHARD``, tests/conftest.py). Their outputs go to
``build/test-<part>.log`` and are printed whole when both have ended; the exit status is the
first non-zero one.

    python scripts/run_tests.py [PYTEST OPTIONS...]
"""

from __future__ import annotations

import os
from pathlib import Path
import signal
import subprocess
import sys

WS = Path(__file__).resolve().parents[1]
PARTS = (('graph', 'graph and not second_lane'), ('library', 'not graph or second_lane'))


def main(argv: list[str]) -> int:
    logs = WS / 'build'
    logs.mkdir(exist_ok=True)
    procs = []
    for k, (name, selection) in enumerate(PARTS):
        env = dict(os.environ, HEXAPOD_TEST_SHARD=f'{k}/{len(PARTS)}')
        log = (logs / f'test-{name}.log').open('w')
        cmd = [sys.executable, '-m', 'pytest', '-m', selection, *argv]
        procs.append(
            (name, log, subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env))
        )
    try:
        codes = [proc.wait() for _, _, proc in procs]
    except KeyboardInterrupt:
        for _, _, proc in procs:
            proc.send_signal(signal.SIGINT)
        codes = [proc.wait() for _, _, proc in procs]
    for (name, log, _), code in zip(procs, codes):
        log.close()
        print(f'==================== {name} tests (exit status {code}) ====================')
        sys.stdout.write((logs / f'test-{name}.log').read_text())
    # pytest's 5: nothing selected, not a failure of one part
    failed = [code for code in codes if code not in (0, 5)]
    return failed[0] if failed else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
