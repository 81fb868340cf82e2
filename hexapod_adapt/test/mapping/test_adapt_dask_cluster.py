# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
generate_map on a Dask cluster as a user runs one.

A scheduler and two workers are separate processes, started as `dask scheduler` and `dask
worker` start them on a cluster's nodes. A worker killed mid-run loses nothing (the scheduler
gives its tasks to the other), the map generator killed mid-run resumes from its checkpoint,
and the map is the one a local run of the same seed makes.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
import signal
import subprocess
import sys
import time

from hexapod_adapt.mapping.archive import load_archive
import numpy as np
import pytest

pytestmark = pytest.mark.slow
SETTINGS = ['--niches', '40', '--evaluations', '360', '--seed', '7', '--lag', '16']
SETTINGS += ['--checkpoint-every', '0.3', '--log-every', '0.3', '--quiet']


def _dask(*args: str, log: Path) -> subprocess.Popen:
    """Start a `dask` command (scheduler or worker) in a process group of its own."""
    with log.open('w') as out:
        return subprocess.Popen(
            [str(Path(sys.executable).with_name('dask')), *args],
            stdout=out,
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )


def _wait(predicate, timeout: float, what: str):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError(f'timed out after {timeout:g} s waiting for {what}')


def _evaluations(log: Path) -> int:
    """Return the evaluations the newest progress line of a generate_map log counts."""
    try:
        lines = log.read_text().splitlines()
        return json.loads(lines[-1])['evaluations'] if lines else 0
    except (OSError, ValueError, KeyError):
        return 0


def _generate(out: Path, *extra: str) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, '-m', 'hexapod_adapt.mapping.generate_map_cli', '--out', str(out)]
        + SETTINGS
        + list(extra),
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )


def _stop(proc: subprocess.Popen) -> None:
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGKILL)
    proc.wait(30)


def test_a_map_made_on_a_cluster_survives_a_lost_worker_and_resumes_exactly(tmp_path):
    reference = tmp_path / 'local' / 'map.npz'
    local = _generate(reference, '--workers', '2')
    assert local.wait(600) == 0, local.stdout.read()

    addr_file = tmp_path / 'scheduler.json'
    scheduler = _dask(
        'scheduler', '--scheduler-file', str(addr_file), '--port', '0', '--no-dashboard',
        log=tmp_path / 'scheduler.log',
    )  # fmt: skip
    workers = []
    try:
        address = _wait(
            lambda: (
                addr_file.is_file() and json.loads(addr_file.read_text() or '{}').get('address')
            ),
            60,
            'the scheduler to write its address',
        )
        for k in range(2):
            workers.append(
                _dask(
                    'worker',
                    '--scheduler-file',
                    str(addr_file),
                    '--nworkers',
                    '1',
                    '--nthreads',
                    '1',
                    '--no-dashboard',
                    log=tmp_path / f'worker{k}.log',
                )  # fmt: skip
            )
        out = tmp_path / 'cluster' / 'map.npz'
        log = Path(f'{out}.log.jsonl')
        run = _generate(out, '--backend', 'dask', '--scheduler', address)
        # a worker lost a third of the way: its tasks go to the other one
        _wait(lambda: _evaluations(log) >= 120, 300, 'a third of the evaluations')
        _stop(workers[0])
        # the generator killed two thirds of the way: it resumes from its checkpoint
        _wait(lambda: _evaluations(log) >= 240 or run.poll() is not None, 300, 'two thirds')
        run.kill()
        run.wait(30)
        resumed = _generate(out, '--backend', 'dask', '--scheduler', address, '--resume')
        text = resumed.communicate(timeout=600)[0]
        assert resumed.returncode == 0, text
    finally:
        for proc in [*workers, scheduler]:
            _stop(proc)
    made, ref = load_archive(out), load_archive(reference)
    assert made.metadata['evaluations'] == ref.metadata['evaluations'] == 360
    np.testing.assert_array_equal(made.fitness, ref.fitness)
    np.testing.assert_array_equal(made.genotypes, ref.genotypes)
    assert made.n_filled > 0
