# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The commands the user's guides show are run exactly as written, through the real graph.

The commands are read from the documents themselves (an indented code block under a heading),
so a guide that changes its commands changes what is tested. A background graph is started as
the guide says (``python scripts/launch.py PROFILE ...``) and the client command is run in a
shell that sourced ``scripts/env.sh``, as a user's second shell has.
"""

from __future__ import annotations

import itertools
import os
from pathlib import Path
import re
import shlex
import signal
import subprocess

import pytest

from conftest import tree_state, worker_slice

pytestmark = [pytest.mark.ros, pytest.mark.slow]
WS = Path(__file__).resolve().parents[2]
#: Within 0-101 (ROS 2's advice on Linux), apart from the other tests' 1-80 (tests/conftest.py).
GUIDE_DOMAINS = worker_slice(range(81, 102))
_domains = (GUIDE_DOMAINS[(os.getpid() + k) % len(GUIDE_DOMAINS)] for k in itertools.count())


def code_block(doc: str, heading: str) -> list[str]:
    """Return the commands of the first indented code block under ``heading`` in ``doc``."""
    text = (WS / doc).read_text()
    start = text.index(f'\n{heading}\n')
    block, started = [], False
    for line in text[start:].splitlines()[1:]:
        if line.startswith('    '):
            started = True
            block.append(line[4:])
        elif started and line.strip():
            break
    commands = []
    for line in block:
        line = re.sub(r'\s+#.*$', '', line)  # the comment
        line = re.sub(r'\s*\[[^\]]*\]', '', line)  # an optional part: [--archive MAP]
        if line.strip():
            commands.append(line.strip())
    return commands


def one(commands: list[str], prefix: str) -> str:
    """Return the one command that starts with ``prefix``."""
    (found,) = [c for c in commands if c.startswith(prefix)]
    return found


def in_a_shell(command: str) -> list[str]:
    """A user's shell: the workspace sourced, then the command."""
    return ['bash', '-c', f'source scripts/env.sh >/dev/null && {command}']


class Graph:
    """A launch.py graph in the background, on a DDS domain of its own."""

    def __init__(self, command: str, env: dict) -> None:
        self.proc = subprocess.Popen(
            in_a_shell(command),
            cwd=WS,
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            start_new_session=True,
        )

    def stop(self) -> str:
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGINT)
            try:
                self.proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
        return self.proc.stdout.read()


@pytest.fixture
def env(tmp_path):
    """A user's second shell; ROS_HOME (where recordings go) in the test's directory."""
    before = tree_state()
    yield dict(
        os.environ,
        ROS_DOMAIN_ID=str(next(_domains)),
        ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST',
        PYTHONUNBUFFERED='1',
        ROS_HOME=str(tmp_path / 'ros_home'),
    )
    # the commands, run as written from the repository root, leave the source tree as it was
    assert tree_state() == before, sorted(tree_state() ^ before)


def run_against(graph_command: str, client: str, env: dict, timeout: float):
    graph = Graph(graph_command, env)
    try:
        done = subprocess.run(
            in_a_shell(client),
            cwd=WS,
            env=env,
            capture_output=True,
            text=True,
            timeout=timeout,
            stdin=subprocess.DEVNULL,
        )
    finally:
        log = graph.stop()
    return done, log


def test_navigation_guide_using_it_reaches_the_goal(env):
    commands = code_block('docs/navigation.md', '## Using it')
    launch = one(commands, 'python scripts/launch.py navigate-sim')
    client = one(commands, 'navigate_client')
    assert launch == 'python scripts/launch.py navigate-sim --failed-legs 1 2'
    assert client == 'navigate_client 1.5 0.5'
    done, log = run_against(launch, client, env, timeout=240)
    assert done.returncode == 0, done.stdout + done.stderr + log[-4000:]
    assert 'REACHED' in done.stdout, done.stdout


def test_the_readme_navigation_line_is_the_guides():
    # the README's line says the guide's two commands (run above) in one line
    guide = code_block('docs/navigation.md', '## Using it')
    launch = one(
        code_block('README.md', '## Running the graph'), 'python scripts/launch.py navigate'
    )
    line = next(raw for raw in (WS / 'README.md').read_text().splitlines() if launch in raw)
    assert launch == one(guide, 'python scripts/launch.py navigate-sim')
    assert line.split('then:', 1)[1].strip() == one(guide, 'navigate_client')


def test_adaptation_guide_adapting_succeeds(env):
    commands = code_block('docs/adaptation.md', '## Adapting')
    launch = one(commands, 'python scripts/launch.py adapt-sim')
    client = one(commands, 'ros2 run hexapod_adapt adapt_client')
    done, log = run_against(launch, client, env, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr + log[-4000:]
    assert re.search(r'^done: gait found: ', done.stdout, re.M), done.stdout
    # the run's recording: under ROS_HOME, as ROS 2 keeps its logs
    assert list((Path(env['ROS_HOME']) / 'adaptation_runs').glob('adapt_*.mcap')), log[-3000:]


def test_the_readme_adaptation_lines_succeed(env):
    commands = code_block('README.md', '## Running the graph')
    launch = one(commands, 'python scripts/launch.py adapt-sim')
    client = one(commands, 'adapt_client')
    done, log = run_against(launch, client, env, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr + log[-4000:]
    assert re.search(r'^done: gait found: ', done.stdout, re.M), done.stdout


DEAD_SERVO_CLIENT = """
import time, rclpy
from hexapod_util.ros_glue import EVENTS
from hexapod_msgs.msg import ServoFailure
from std_srvs.srv import SetBool, Trigger
rclpy.init()
node = rclpy.create_node('operator')
seen = []
node.create_subscription(ServoFailure, 'servo_failures', seen.append, EVENTS)
def call(kind, name, request):
    client = node.create_client(kind, name)
    assert client.wait_for_service(timeout_sec=60), name
    future = client.call_async(request)
    rclpy.spin_until_future_complete(node, future, timeout_sec=30)
    return future.result()
print('arm', call(SetBool, 'bridge_node/arm', SetBool.Request(data=True)).success)
print('check', call(Trigger, 'bridge_node/check_servos', Trigger.Request()).message)
end = time.monotonic() + 60
while not seen and time.monotonic() < end:
    rclpy.spin_once(node, timeout_sec=0.1)
for m in seen[:1]:
    print('DEAD', m.servo_id, m.leg, m.joint)
"""


def test_the_bridge_guide_rehearses_a_dead_servo_on_the_cpp_firmware(env):
    commands = code_block('docs/bridge.md', '## Running it')
    launch = one(commands, 'python scripts/launch.py emulated-robot --firmware')
    assert launch == 'python scripts/launch.py emulated-robot --firmware native --dead-servo 6'
    client = f'python -c {shlex.quote(DEAD_SERVO_CLIENT)}'
    done, log = run_against(launch, client, env, timeout=180)
    assert 'DEAD 6 2 femur' in done.stdout, done.stdout + done.stderr + log[-3000:]
    assert 'protocol 1.1' in done.stdout  # the C++ module answered the HELLO


def test_the_bridge_guide_rehearses_the_robots_own_leg_numbering(env):
    commands = code_block('docs/bridge.md', '## Running it')
    launch = one(commands, 'python scripts/launch.py emulated-robot --leg-map')
    assert '--leg-map 1 6 5 4 3 2' in launch and '--dead-servo 6' in launch
    client = f'python -c {shlex.quote(DEAD_SERVO_CLIENT)}'
    done, log = run_against(launch, client, env, timeout=180)
    # servo 6 is the femur of the robot's leg 2: URDF leg 6 in the clockwise numbering
    assert 'DEAD 6 6 femur' in done.stdout, done.stdout + done.stderr + log[-3000:]


def test_the_bridge_guide_checks_the_leg_numbering_with_leg_check(env):
    commands = code_block('docs/bridge.md', '## Running it')
    launch = one(commands, 'python scripts/launch.py emulated-robot --leg-map')
    check = one(commands, 'leg_check')
    assert check == 'leg_check 2 --arm'
    done, log = run_against(launch, check, env, timeout=180)
    assert done.returncode == 0, done.stdout + done.stderr + log[-3000:]
    says = "URDF leg 2, mounted at +60 deg from the body's +x axis (counter-clockwise seen from"
    assert says in done.stdout and 'robot leg 6 by leg_map [1, 6, 5, 4, 3, 2]' in done.stdout


def test_emulated_robot_refuses_failed_legs_saying_what_to_use(env):
    done = subprocess.run(
        in_a_shell('python scripts/launch.py emulated-robot --failed-legs 1'),
        cwd=WS,
        env=env,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 2 and '--dead-servo ID' in done.stderr, done.stderr
