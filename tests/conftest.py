# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Shared fixtures for the cross-package integration tests.

ROS 2 nodes started as separate processes from the install space, and an in-process rclpy harness
on a private context and a unique DDS domain, talking over loopback.
"""

from __future__ import annotations

import itertools
import os
from pathlib import Path
import signal
import subprocess
import sys
import threading
import time
from typing import Any, Callable

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.mapping.simulation import simulation_fingerprint
from hexapod_sim import create_simulator, evaluate_gait
from hexapod_sim.sampling import random_feasible_genotypes
import numpy as np
import pytest

WS = Path(__file__).resolve().parent.parent
FAILED = [2]  # the legs the small archive's damaged speeds are measured with


@pytest.fixture(scope='module')
def small_archive(tmp_path_factory):
    """12 feasible gaits, each its own niche, with their map-generation evaluations."""
    with create_simulator() as sim:
        genes, results = random_feasible_genotypes(12, seed=77, sim=sim)
        damaged = [
            evaluate_gait(g, sim, collisions_fatal=False, failed_legs=FAILED).speed for g in genes
        ]
    desc = np.array([r.descriptor for r in results])
    archive = Archive(
        desc,
        np.array([r.fitness for r in results]),
        desc,
        genes,
        {'seed': 77, 'evaluations': 12, **simulation_fingerprint('pybullet')},
    )
    path = archive.save(tmp_path_factory.mktemp('archive') / 'map.npz')
    return path, archive, np.array(damaged)


def status_log_qos():
    """The status-as-a-log reader profile (hexapod_util.ros_glue.STATUS_LOG)."""
    from hexapod_util.ros_glue import STATUS_LOG

    return STATUS_LOG


_domain_ids = itertools.count((os.getpid() % 40) + 1)


def executable(pkg: str, exe: str) -> Path:
    return WS / 'install' / pkg / 'lib' / pkg / exe


class NodeProcess:
    """A node started from install/<pkg>/lib/<pkg>/<exe> (what `ros2 run` executes)."""

    def __init__(
        self,
        pkg: str,
        exe: str,
        domain_id: int,
        log_dir: Path,
        params: dict[str, Any] | None = None,
        args: list[str] | None = None,
        env: dict[str, str] | None = None,
    ):
        self.log_path = log_dir / f'{exe}.log'
        cmd = [str(executable(pkg, exe))] + list(args or [])
        if params:
            from hexapod_util.ros_glue import ros_args

            cmd += ros_args(params)
        full_env = dict(
            os.environ,
            ROS_DOMAIN_ID=str(domain_id),
            PYTHONUNBUFFERED='1',
            RCUTILS_LOGGING_BUFFERED_STREAM='0',
            **(env or {}),
        )
        self._log = open(self.log_path, 'w')
        self.proc = subprocess.Popen(
            cmd, stdout=self._log, stderr=subprocess.STDOUT, env=full_env, start_new_session=True
        )

    def alive(self) -> bool:
        return self.proc.poll() is None

    def log(self) -> str:
        if not self._log.closed:
            self._log.flush()
        return self.log_path.read_text()

    def stop(self, timeout: float = 10.0) -> int:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
            try:
                self.proc.wait(timeout)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait()
        self._log.close()
        return self.proc.returncode


class RosHarness:
    """An rclpy node on its own context, spun by a background executor thread."""

    def __init__(self, domain_id: int):
        import rclpy
        from rclpy.executors import MultiThreadedExecutor

        self.rclpy = rclpy
        self.domain_id = domain_id
        self.context = rclpy.Context()
        rclpy.init(context=self.context, domain_id=domain_id)
        self.node = rclpy.create_node('test_harness', context=self.context)
        self.executor = MultiThreadedExecutor(num_threads=2, context=self.context)
        self.executor.add_node(self.node)
        self._thread = threading.Thread(target=self.executor.spin, daemon=True)
        self._thread.start()

    def collect(self, msg_type, topic: str, qos) -> list:
        """Subscribe and return the (growing) list of received messages."""
        received: list = []
        self.node.create_subscription(msg_type, topic, received.append, qos)
        return received

    def call(self, srv_type, name: str, request, timeout: float = 20.0):
        client = self.node.create_client(srv_type, name)
        if not client.wait_for_service(timeout_sec=timeout):
            raise TimeoutError(f'service {name} not available')
        future = client.call_async(request)
        wait_for(future.done, timeout, f'response from {name}')
        return future.result()

    def close(self) -> None:
        self.executor.shutdown()
        self.node.destroy_node()
        self.rclpy.try_shutdown(context=self.context)


def wait_for(
    predicate: Callable[[], Any], timeout: float, what: str = 'condition', period: float = 0.02
):
    """Poll predicate until truthy; raise AssertionError naming what did not happen."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(period)
    raise AssertionError(f'timed out after {timeout:g} s waiting for {what}')


# A separate process whose node is not the bridge publishes one ServoFailure on servo_failures
# (subscribers name a message's sender by its node, so the test harness cannot play it).
_IMPOSTOR = """
import rclpy, sys, time
from hexapod_util.ros_glue import EVENTS
from hexapod_msgs.msg import ServoFailure
rclpy.init()
node = rclpy.create_node(sys.argv[1])
pub = node.create_publisher(ServoFailure, 'servo_failures', EVENTS)
end = time.monotonic() + 30
while pub.get_subscription_count() < 1 and time.monotonic() < end:
    time.sleep(0.05)
pub.publish(ServoFailure(servo_id=int(sys.argv[2]), robot_leg=int(sys.argv[3]),
                         leg=int(sys.argv[3]), joint=sys.argv[4]))
time.sleep(5)
"""


def publish_servo_report_as(
    node_name: str, domain_id: int, servo_id: int, leg: int, joint: str
) -> subprocess.Popen:
    """Start a process whose node ``node_name`` reports ``servo_id`` (on ``leg``) dead."""
    env = dict(os.environ, ROS_DOMAIN_ID=str(domain_id))
    args = [node_name, str(servo_id), str(leg), joint]
    return subprocess.Popen([sys.executable, '-c', _IMPOSTOR, *args], env=env)


@pytest.fixture
def domain_id(monkeypatch) -> int:
    did = next(_domain_ids)
    monkeypatch.setenv('ROS_DOMAIN_ID', str(did))
    monkeypatch.setenv('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    return did


@pytest.fixture
def ros(domain_id):
    harness = RosHarness(domain_id)
    yield harness
    harness.close()


@pytest.fixture
def launch(domain_id, tmp_path):
    """Start nodes with ``launch(pkg, exe, params=..., args=...)``; all stop at teardown."""
    started: list[NodeProcess] = []

    def _launch(pkg: str, exe: str, **kwargs) -> NodeProcess:
        node = NodeProcess(pkg, exe, domain_id, tmp_path, **kwargs)
        started.append(node)
        return node

    yield _launch
    for node in started:
        node.stop()
        # shown by pytest only when the test failed
        tail = node.log_path.read_text().splitlines()[-25:]
        print(f'----- {node.log_path.name} (last {len(tail)} lines) -----', *tail, sep='\n')
