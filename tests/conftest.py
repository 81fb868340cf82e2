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
import queue
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


#: DDS domains of the tests' graphs: within 0-101, the ids ROS 2 advises on Linux (higher ones
#: can take ephemeral ports). 1-80 here, in turn from a place of this process's own; the
#: guides' commands (tests/workspace/test_documented_commands.py) take 81-101.
#: Two pytest processes at once (make test's) each take their own slice: they never share one.
def worker_slice(domains: range) -> range:
    """
    Return the part of ``domains`` this pytest process owns (all of it when it runs alone).

    scripts/run_tests.py runs two processes at once, each with ``HEXAPOD_TEST_SHARD=k/n``.
    """
    shard = os.environ.get('HEXAPOD_TEST_SHARD', '')
    if not shard:
        return domains
    k, n = (int(x) for x in shard.split('/'))
    return domains[k::n]


TEST_DOMAINS = worker_slice(range(1, 81))
_domain_ids = (TEST_DOMAINS[(os.getpid() + k) % len(TEST_DOMAINS)] for k in itertools.count())


def next_domain() -> int:
    """A DDS domain no other graph of this run is using now."""
    return next(_domain_ids)


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
        from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
        from rclpy.executors import MultiThreadedExecutor

        self.rclpy = rclpy
        self.domain_id = domain_id
        self.context = rclpy.Context()
        rclpy.init(context=self.context, domain_id=domain_id)
        self.node = rclpy.create_node('test_harness', context=self.context)
        self._adapt_client = None
        # rclpy's ActionClient races when one thread sends while another spins it: an answer
        # that arrives before send_goal_async (or get_result_async, cancel_goal_async) has filed
        # its request is dropped, 'Ignoring unexpected goal response' (ros2/rclpy#1123; twice in
        # CI). Clients made by action_client() are served in this mutually exclusive group, and
        # on_spin_thread() sends from a callback of the same group: no answer overtakes its send.
        self.goals = MutuallyExclusiveCallbackGroup()
        self._jobs: queue.SimpleQueue = queue.SimpleQueue()
        self._job_guard = self.node.create_guard_condition(self._run_jobs, self.goals)
        self.executor = MultiThreadedExecutor(num_threads=2, context=self.context)
        self.executor.add_node(self.node)
        self._thread = threading.Thread(target=self.executor.spin, daemon=True)
        self._thread.start()

    def _run_jobs(self) -> None:
        while True:
            try:
                job = self._jobs.get_nowait()
            except queue.Empty:
                return
            job()

    def on_spin_thread(self, call: Callable[[], Any], timeout: float = 10.0) -> Any:
        """Run ``call`` in the ``goals`` callback group on the spin thread; return its value."""
        box: dict[str, Any] = {}
        ran = threading.Event()

        def job() -> None:
            try:
                box['value'] = call()
            except Exception as error:  # noqa: BLE001 - raised again in the caller's thread
                box['error'] = error
            finally:
                ran.set()

        self._jobs.put(job)
        self._job_guard.trigger()
        if not ran.wait(timeout):
            raise TimeoutError(f'the spin thread did not run {call!r} within {timeout:g} s')
        if 'error' in box:
            raise box['error']
        return box['value']

    def action_client(self, action_type, name: str, **kwargs):
        """An action client of the harness node, served in the ``goals`` group."""
        from rclpy.action import ActionClient

        return ActionClient(self.node, action_type, name, callback_group=self.goals, **kwargs)

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

    def play_bridge(self) -> Callable[[Any], None]:
        """
        Play bridge_node's servo reports: return ``report(ServoFailure)``.

        It publishes the report on servo_failures and holds the servo dead on
        ``test_harness/get_servo_failures``, as bridge_node does, for nodes configured with
        ``bridge_node: test_harness``.
        """
        from hexapod_msgs.msg import ServoFailure
        from hexapod_msgs.srv import GetServoFailures
        from hexapod_util.ros_glue import EVENTS

        held: dict[int, Any] = {}

        def answer(request, response):
            response.failures = list(held.values())
            return response

        self.node.create_service(GetServoFailures, '~/get_servo_failures', answer)
        pub = self.node.create_publisher(ServoFailure, 'servo_failures', EVENTS)
        wait_for(lambda: pub.get_subscription_count() > 0, 30, 'a subscriber of servo_failures')

        def report(msg) -> None:
            held.setdefault(msg.servo_id, msg)
            pub.publish(msg)

        return report

    def send_adapt(self, goal, timeout: float = 30.0) -> 'AdaptRun':
        """Send a goal to adapt_node's ``adapt`` action (waiting for the server); do not wait."""
        from hexapod_msgs.action import Adapt
        from hexapod_util.ros_glue import ACTION_QOS

        if self._adapt_client is None:
            self._adapt_client = self.action_client(Adapt, 'adapt', **ACTION_QOS)
        if not self._adapt_client.wait_for_server(timeout_sec=timeout):
            raise TimeoutError('action adapt not available')
        return AdaptRun(self, self._adapt_client, goal)

    def adapt(self, goal, timeout: float = 20.0):
        """Run one adapt goal to its end and return its result (``Adapt.Result``)."""
        run = self.send_adapt(goal, timeout)
        wait_for(run.done, timeout, 'the result of adapt')
        return run.result()

    def close(self) -> None:
        self.executor.shutdown()
        self.node.destroy_node()
        self.rclpy.try_shutdown(context=self.context)


class AdaptRun:
    """One goal sent to the ``adapt`` action: its answer, feedback and result as they arrive."""

    def __init__(self, ros: RosHarness, client, goal) -> None:
        self.feedback: list = []  # Adapt.Feedback, one per trial and one per note
        self.arrived: list[float] = []  # time.monotonic() each feedback arrived
        self._ros = ros
        self.sent = ros.on_spin_thread(
            lambda: client.send_goal_async(goal, feedback_callback=self._on_feedback)
        )
        self._answer = None

    def _on_feedback(self, message) -> None:
        self.arrived.append(time.monotonic())
        self.feedback.append(message.feedback)

    @property
    def trials(self) -> list:
        """The feedback of each trial walked (the notes left out)."""
        return [f for f in self.feedback if f.trial.trial > 0]

    def notes_after(self, t: float) -> list[tuple[float, str]]:
        """The notes (arrival time, text) that arrived after monotonic time ``t``."""
        return [(a, f.note) for a, f in zip(self.arrived, self.feedback) if a > t and f.note]

    def handle(self, timeout: float = 30.0):
        """Return the goal's handle once adapt_node answered (accepted or rejected)."""
        wait_for(self.sent.done, timeout, 'the goal response of adapt')
        return self.sent.result()

    def done(self) -> bool:
        """True when the goal was rejected, or its result arrived."""
        if not self.sent.done():
            return False
        handle = self.sent.result()
        if not handle.accepted:
            return True
        if self._answer is None:
            self._answer = self._ros.on_spin_thread(handle.get_result_async)
        return self._answer.done()

    @property
    def status(self) -> int:
        """The goal's final ``GoalStatus`` (``done()`` first)."""
        return self._answer.result().status

    def result(self):
        """The goal's ``Adapt.Result`` (``done()`` first; the goal was accepted)."""
        assert self.done() and self._answer is not None, 'the goal was rejected or is running'
        return self._answer.result().result

    def cancel(self, timeout: float = 10.0) -> bool:
        """Ask for a cancel; return whether adapt_node accepted it."""
        future = self._ros.on_spin_thread(self.handle().cancel_goal_async)
        wait_for(future.done, timeout, 'the answer to a cancel')
        return len(future.result().goals_canceling) > 0


def set_adapt_parameter(ros, name: str, value):
    """Set one of adapt_node's parameters (an rcl_interfaces ParameterValue); its result."""
    from rcl_interfaces.msg import Parameter
    from rcl_interfaces.srv import SetParameters

    req = SetParameters.Request(parameters=[Parameter(name=name, value=value)])
    return ros.call(SetParameters, 'adapt_node/set_parameters', req).results[0]


def fast_sim_graph(launch, failed_legs, **adapt_params) -> tuple[NodeProcess, ...]:
    """(sim_node, gait_node, adapt_node): the sim as fast as it runs, with ``failed_legs``."""
    sim = launch(
        'hexapod_sim', 'sim_node', params={'real_time_factor': 0.0, 'failed_legs': failed_legs}
    )
    gait = launch('hexapod_gait', 'gait_node', params={'initial_preset': ''})
    return sim, gait, launch('hexapod_adapt', 'adapt_node', params=adapt_params)


#: What building and testing write in the tree (ignored, and no guide's command writes there).
BUILD_OUTPUTS = ('build/', 'install/', 'log/', '.venv/', '.pytest_cache/', '.hypothesis/')


def tree_state() -> set[str]:
    """Every file git sees changed, untracked or ignored in the tree, but the build's outputs."""
    status = subprocess.run(
        ['git', 'status', '--porcelain', '--ignored', '--untracked-files=all'],
        cwd=WS, capture_output=True, text=True, check=True,
    ).stdout  # fmt: skip
    return {
        line
        for line in status.splitlines()
        if not line[3:].startswith(BUILD_OUTPUTS)
        and '__pycache__/' not in line
        and not line.endswith('.pyc')
    }


def wait_for(
    predicate: Callable[[], Any], timeout: float, what: str = 'condition', period: float = 0.02
):
    """Poll predicate until truthy; raise AssertionError naming what did not happen."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()  # asked once more after the deadline: a stalled poll is no failure
        if value:
            return value
        if time.monotonic() >= deadline:
            raise AssertionError(f'timed out after {timeout:g} s waiting for {what}')
        time.sleep(period)


# A separate process whose node is not the bridge publishes ServoFailure reports on
# servo_failures: ``times`` nodes one after another (NAME_0, NAME_1, ... when several), each
# publishing one report as soon as a subscriber matched, then lingering ``linger`` s after it
# was delivered (0: destroyed at once, the forger who leaves). It prints how many of its reports
# the subscriber acknowledged: one not acknowledged in 10 s is left behind with its node.
_IMPOSTOR = """
import rclpy, sys, time
from hexapod_util.ros_glue import EVENTS
from hexapod_msgs.msg import ServoFailure
from rclpy.duration import Duration
name, servo, leg, joint, times, linger = sys.argv[1:]
rclpy.init()
acked = 0
for i in range(int(times)):
    node = rclpy.create_node(name if int(times) == 1 else f'{name}_{i}')
    pub = node.create_publisher(ServoFailure, 'servo_failures', EVENTS)
    end = time.monotonic() + 30
    while pub.get_subscription_count() < 1 and time.monotonic() < end:
        time.sleep(0.01)
    pub.publish(ServoFailure(servo_id=int(servo), robot_leg=int(leg), leg=int(leg), joint=joint))
    acked += pub.wait_for_all_acked(Duration(seconds=10))  # delivered: then it leaves
    time.sleep(float(linger))
    node.destroy_node()
    time.sleep(0.5)  # the next forger is a new node: let the graph see this one go
print(f'acked {acked}', flush=True)
"""


def publish_servo_report_as(
    node_name: str,
    domain_id: int,
    servo_id: int,
    leg: int,
    joint: str,
    times: int = 1,
    linger: float = 5.0,
) -> subprocess.Popen:
    """
    Start a process whose node ``node_name`` reports ``servo_id`` (on ``leg``) dead.

    Its stdout (a pipe) ends with ``acked N``: the reports the subscriber acknowledged.
    """
    env = dict(os.environ, ROS_DOMAIN_ID=str(domain_id))
    args = [node_name, str(servo_id), str(leg), joint, str(times), str(linger)]
    return subprocess.Popen(
        [sys.executable, '-c', _IMPOSTOR, *args], env=env, stdout=subprocess.PIPE, text=True
    )


def forgers_are_ignored_and_named(node, domain_id: int, tries: int = 20) -> None:
    """
    Nodes that are not the bridge report servo 5 dead, ``tries`` times: every report ignored.

    Each forger publishes one report and leaves at once (its node destroyed once the report was
    delivered); then one that lingers, which is named. A forger that left at once is named when
    the graph learned its node's name in time, else the refusal says it left (rclpy does not say
    who sent a message: the bridge is asked, and the graph watched for who joins).
    """
    from hexapod_adapt.ros.servo_reports import ASK_TIMEOUT_S, NAME_WAIT_S

    ignored = 'servo 5 (leg 3) reported dead: servo report ignored: the bridge /test_harness does'
    quick = publish_servo_report_as('not_the_bridge', domain_id, 5, 3, 'tibia', tries, linger=0)
    out, _ = quick.communicate(timeout=tries * 45)
    assert quick.returncode == 0
    acked = int(out.split()[-1])
    assert acked >= tries // 2, out
    # adapt_node judges one report at a time: each may take the bridge's answer and a wait for
    # the sender's name (a loaded machine judged one in 3 s, and fell behind the forgers). It
    # judges what reaches it: Fast DDS lost reports it had acknowledged when their writer left at
    # once (CI: 19 of 20 refused, 2026-12-02; 18 of 20 acknowledged, 2026-12-03), so the wait
    # ends when all are judged or none has come for a while
    judging = tries * (ASK_TIMEOUT_S + NAME_WAIT_S) + 30
    quiet = 3 * (ASK_TIMEOUT_S + NAME_WAIT_S)
    deadline, seen, since = time.monotonic() + judging, -1, time.monotonic()
    while time.monotonic() < deadline:
        count = node.log().count(ignored)
        if count >= acked:
            break
        if count != seen:
            seen, since = count, time.monotonic()
        elif time.monotonic() - since > quiet:
            break
        time.sleep(0.1)
    time.sleep(ASK_TIMEOUT_S + NAME_WAIT_S)  # one not acknowledged may still be judged
    lines = [line for line in node.log().splitlines() if ignored in line]
    # most are judged (a node that dropped reports of its own would fall far short)
    assert tries // 2 <= len(lines) <= tries, f'{len(lines)} of {acked} acknowledged refused'
    named = [i for i, line in enumerate(lines) if f'/not_the_bridge_{i}' in line]
    left = [i for i, line in enumerate(lines) if 'the sender left at once' in line]
    print(
        f'forgers who left at once: {acked} of {tries} acknowledged, {len(lines)} refused,'
        f' {len(named)} named, {len(left)} said to have left'
    )
    assert all('not hold servo 5 dead' in line for line in lines)
    assert all('/not_the_bridge_' in line or i in left for i, line in enumerate(lines))
    lingering = publish_servo_report_as('not_the_bridge', domain_id, 5, 3, 'tibia')
    count = len(lines)
    wait_for(lambda: node.log().count(ignored) == count + 1, 30, 'a lingering forger refused')
    last = [line for line in node.log().splitlines() if ignored in line][-1]
    assert last.endswith('/not_the_bridge') or '/not_the_bridge,' in last, last
    out, _ = lingering.communicate(timeout=30)
    assert out.split()[-1] == '1', out  # its one report acknowledged


@pytest.fixture
def domain_id(monkeypatch) -> int:
    did = next_domain()
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
        if exe == 'adapt_node':
            # each test its own re-scores: a bank other tests cached would change a blind run
            own = {'prior_cache_dir': str(tmp_path / 'prior_cache')}
            kwargs['params'] = {**own, **(kwargs.get('params') or {})}
        node = NodeProcess(pkg, exe, domain_id, tmp_path, **kwargs)
        started.append(node)
        return node

    yield _launch
    for node in started:
        node.stop()
        # shown by pytest only when the test failed
        tail = node.log_path.read_text().splitlines()[-25:]
        print(f'----- {node.log_path.name} (last {len(tail)} lines) -----', *tail, sep='\n')
