# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The launch files (for full ROS installs) compile; scripts/launch.py runs a graph.

scripts/launch.py starts a working graph and stops it cleanly on Ctrl-C.
"""

from __future__ import annotations

import ast
import os
from pathlib import Path
import py_compile
import signal
import subprocess
import sys
import time
import warnings

from hexapod_util.ros_glue import TEARDOWN_LIMIT_S
from nav_msgs.msg import Odometry
import pytest
from rclpy.qos import QoSProfile, ReliabilityPolicy

from conftest import tree_state, wait_for, WS


@pytest.mark.parametrize(
    'path', sorted(WS.glob('hexapod_*/launch/*.launch.py')), ids=lambda p: p.name
)
def test_launch_files_compile(path: Path):
    py_compile.compile(str(path), doraise=True)
    assert 'generate_launch_description' in path.read_text()


@pytest.mark.ros
@pytest.mark.parametrize('ctrl_c', ['launcher', 'terminal'])
def test_launcher_starts_the_sim_graph_and_stops_on_ctrl_c(ros, domain_id, tmp_path, ctrl_c):
    """
    Ctrl-C stops every node cleanly.

    'terminal': the SIGINT reaches the launcher and every node (one process group), and the
    launcher forwards one more: the second must not break the nodes' clean-up.
    """
    odom = ros.collect(
        Odometry, 'odom', QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE)
    )
    log = open(tmp_path / 'launch.log', 'w')
    # started with SIGINT ignored, as a background job of a non-interactive shell would be: Ctrl-C
    # (SIGINT) must stop the launcher and its nodes anyway
    proc = subprocess.Popen(
        [
            sys.executable,
            str(WS / 'scripts' / 'launch.py'),
            'sim',
            '--rtf',
            '0',
            '--failed-legs',
            '2',
        ],
        env=dict(os.environ, ROS_DOMAIN_ID=str(domain_id)),
        stdout=log,
        stderr=subprocess.STDOUT,
        start_new_session=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN),
    )
    try:
        # the tripod walks: odometry moves away from the origin
        wait_for(lambda: odom and math_dist(odom[-1]) > 0.2, 60, 'the simulated robot walking')
    finally:
        if ctrl_c == 'terminal':
            os.killpg(proc.pid, signal.SIGINT)
        else:
            proc.send_signal(signal.SIGINT)
        try:
            code = proc.wait(40)
        except subprocess.TimeoutExpired:
            code = None
        if code is None:  # never leave the graph running after a failure
            os.killpg(proc.pid, signal.SIGKILL)
        log.close()
    text = (tmp_path / 'launch.log').read_text()
    assert '[sim_node]' in text and '[gait_node]' in text
    assert stopped(code, text), text[-2000:]
    assert 'Traceback' not in text, text[text.index('Traceback') - 200 :][:3000]


def _stop(proc: subprocess.Popen, log) -> int | None:
    """Ctrl-C the launcher; return its exit status (None: it had to be killed)."""
    proc.send_signal(signal.SIGINT)
    try:
        code = proc.wait(40)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        code = None
    log.close()
    return code


def stopped(code: int | None, text: str) -> bool:
    """
    Return whether the launcher and its nodes stopped at Ctrl-C as a user needs them to.

    Status 0; or 1 from a node whose middleware hung tearing it down after it had saved its state
    (a Fast DDS participant's deletion, run_node's watchdog: its stacks are in the log), which
    this test reports as a warning, not a failure of the product.
    """
    if code == 0:
        return True
    watchdog = f'Timeout (0:00:{TEARDOWN_LIMIT_S:02.0f})!' in text and 'in destroy_node' in text
    if code == 1 and watchdog and 'still running: sending SIGTERM' not in text:
        warnings.warn('a node hung in its DDS teardown; its watchdog ended it', stacklevel=2)
        return True
    return False


def math_dist(o: Odometry) -> float:
    return (o.pose.pose.position.x**2 + o.pose.pose.position.y**2) ** 0.5


def _declared() -> dict[str, dict[str, object]]:
    """Every node's declared parameters and their defaults (what the YAML files may set)."""
    from hexapod_adapt.ros.adapt_node import PARAMETERS as ADAPT
    from hexapod_bridge.bridge_node import PARAMETERS as BRIDGE
    from hexapod_gait.gait_node import PARAMETERS as GAIT
    from hexapod_navigation.ros.navigate_node import PARAMETERS as NAVIGATE
    from hexapod_sim.sim_node import PARAMETERS as SIM

    nodes = {
        'gait_node': GAIT,
        'sim_node': SIM,
        'bridge_node': BRIDGE,
        'adapt_node': ADAPT,
        'navigate_node': NAVIGATE,
    }
    return {name: {p.name: p.default for p in specs} for name, specs in nodes.items()}


@pytest.mark.parametrize('path', sorted(WS.glob('hexapod_*/config/*.yaml')), ids=lambda p: p.name)
def test_each_parameter_file_names_declared_parameters_of_the_right_type(path: Path):
    from rclpy.parameter import Parameter
    import yaml

    declared = _declared()
    text = yaml.safe_load(path.read_text())
    assert text, f'{path} is empty'
    for node, section in text.items():
        assert node in declared, f'{path}: no node {node}'
        values = section['ros__parameters']
        for name, value in values.items():
            assert name in declared[node], f'{path}: {node} has no parameter {name}'
            default = declared[node][name]
            if isinstance(default, Parameter.Type):  # no default: the declared type
                kind = Parameter.Type.from_parameter_value(value)
                assert kind == default, (path, node, name, kind, default)
            else:
                assert type(value) is type(default), (path, node, name, value, default)


@pytest.mark.ros
def test_the_launcher_takes_a_parameter_file(ros, domain_id, tmp_path):
    """The sim profile with hexapod_sim/config/sim.yaml changed as a user would."""
    import yaml

    params = yaml.safe_load((WS / 'hexapod_sim' / 'config' / 'sim.yaml').read_text())
    params['sim_node']['ros__parameters'].update(engine='mujoco', real_time_factor=0.0)
    mine = tmp_path / 'sim.yaml'
    mine.write_text(yaml.safe_dump(params))
    odom = ros.collect(
        Odometry, 'odom', QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE)
    )
    log = open(tmp_path / 'launch.log', 'w')
    proc = subprocess.Popen(
        [sys.executable, str(WS / 'scripts' / 'launch.py'), 'sim', '--params-file', str(mine)],
        env=dict(os.environ, ROS_DOMAIN_ID=str(domain_id)),
        stdout=log,
        stderr=subprocess.STDOUT,
        start_new_session=True,
    )
    try:
        wait_for(lambda: odom and math_dist(odom[-1]) > 0.05, 60, 'the simulated robot walking')
    finally:
        code = _stop(proc, log)
    text = (tmp_path / 'launch.log').read_text()
    assert 'simulating with the mujoco engine at real_time_factor 0' in text, text[-2000:]
    assert stopped(code, text), text[-2000:]


def _module_dicts(path: Path) -> dict[str, dict]:
    """The module-level ``NAME = {...}`` literals of a Python file, read without importing it."""
    found = {}
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Dict):
            for target in node.targets:
                if isinstance(target, ast.Name):
                    found[target.id] = ast.literal_eval(node.value)
    return found


def _names(expr: ast.expr, dicts: dict[str, dict]) -> set[str]:
    """The argument names a ``configured_node`` argument expression stands for."""
    if isinstance(expr, ast.Name):
        return set(dicts[expr.id])
    if isinstance(expr, ast.BinOp) and isinstance(expr.op, ast.BitOr):
        return _names(expr.left, dicts) | _names(expr.right, dicts)
    return set(ast.literal_eval(expr))  # a tuple of names, () for none


LAUNCH_FILES = sorted(
    p for p in WS.glob('hexapod_*/launch/*.launch.py') if p.name != 'display.launch.py'
)


@pytest.mark.parametrize('path', LAUNCH_FILES, ids=lambda p: p.name)
def test_each_launch_file_takes_a_parameter_file_and_its_arguments_are_node_parameters(
    path: Path,
):
    """
    ``params_file`` defaults to a file of the package's config/.

    Every argument an operator may give is a declared parameter of each node it goes to, and a
    parameter the file can set.
    """
    import yaml

    dicts = _module_dicts(WS / 'hexapod_description/hexapod_description/launch_actions.py')
    dicts |= _module_dicts(path)
    declared = _declared()
    calls = [
        n
        for n in ast.walk(ast.parse(path.read_text()))
        if isinstance(n, ast.Call) and getattr(n.func, 'id', '') in ('configured_node',
                                                                      'params_file_argument')
    ]  # fmt: skip
    files = [ast.literal_eval(c.args[1]) for c in calls if c.func.id == 'params_file_argument']
    assert len(files) == 1, f'{path.name}: one params_file argument'
    package = path.parent.parent
    config = yaml.safe_load((package / 'config' / files[0]).read_text())
    nodes = [c for c in calls if c.func.id == 'configured_node']
    assert nodes, f'{path.name} starts no node through configured_node'
    for call in nodes:
        node = ast.literal_eval(call.args[1])
        arguments = _names(call.args[2], dicts) if len(call.args) > 2 else set()
        unknown = arguments - set(declared[node])
        assert not unknown, f'{path.name}: {node} has no parameter {sorted(unknown)}'
        assert node in config, f'{path.name}: its default file {files[0]} does not name {node}'


def test_the_adapt_sim_file_runs_the_shipped_default_maps_physics():
    """adapt.yaml's sim_node walks trials on the engine and steps per row that made the map."""
    from hexapod_adapt.mapping.archive import load_archive
    from hexapod_adapt.mapping.maps import shipped_map
    from hexapod_adapt.mapping.simulation import engine_of_map, trial_substeps
    import yaml

    sim = yaml.safe_load((WS / 'hexapod_adapt/config/adapt.yaml').read_text())['sim_node']
    archive = load_archive(shipped_map())
    engine = engine_of_map(archive)
    assert sim['ros__parameters']['engine'] == engine
    assert sim['ros__parameters']['substeps'] == trial_substeps(archive, engine)


#: Each launcher profile: its options, a parameter file of its package, the nodes it starts, and
#: a parameter that file sets (changed in the test's copy), with the option that wins over it.
PROFILE_FILES = {
    'sim': (['--rtf', '0'], 'hexapod_sim/config/sim.yaml', ('sim_node', 'engine', 'mujoco')),
    'adapt-sim': ([], 'hexapod_adapt/config/adapt.yaml', ('adapt_node', 'max_trials', 7)),
    'navigate-sim': (
        [], 'hexapod_navigation/config/navigate.yaml', ('navigate_node', 'tolerance', 0.25)
    ),
    'emulated-robot': (
        [], 'hexapod_bridge/config/robot.yaml', ('bridge_node', 'trial_duration', 4.0)
    ),
    'robot': (
        ['--navigate'],
        'hexapod_navigation/config/navigate_robot.yaml',
        ('navigate_node', 'max_range', 7.0),
    ),
}  # fmt: skip
NODES = {
    'sim': {'gait_node', 'sim_node'},
    'adapt-sim': {'gait_node', 'sim_node', 'adapt_node'},
    'navigate-sim': {'gait_node', 'sim_node', 'navigate_node'},
    'emulated-robot': {'bridge_node'},
    'robot': {'bridge_node', 'navigate_node'},
}


def _parameter(ros, node: str, name: str):
    from rcl_interfaces.srv import GetParameters
    from rclpy.parameter import parameter_value_to_python

    answer = ros.call(
        GetParameters, f'/{node}/get_parameters', GetParameters.Request(names=[name])
    )
    return parameter_value_to_python(answer.values[0])


@pytest.mark.slow
@pytest.mark.ros
@pytest.mark.parametrize('with_file', [False, True], ids=['defaults', 'params-file'])
@pytest.mark.parametrize('profile', sorted(PROFILE_FILES))
def test_every_profile_starts_with_its_defaults_and_with_a_parameter_file(
    ros, domain_id, tmp_path, profile: str, with_file: bool
):
    import yaml

    options, file, (node, name, value) = PROFILE_FILES[profile]
    command = [sys.executable, str(WS / 'scripts' / 'launch.py'), profile, *options]
    if with_file:
        params = yaml.safe_load((WS / file).read_text())
        assert params[node]['ros__parameters'].get(name) != value  # the test changes it
        params[node]['ros__parameters'][name] = value
        mine = tmp_path / 'mine.yaml'
        mine.write_text(yaml.safe_dump(params))
        command += ['--params-file', str(mine)]
    log = open(tmp_path / 'launch.log', 'w')
    proc = subprocess.Popen(
        command,
        env=dict(os.environ, ROS_DOMAIN_ID=str(domain_id)),
        stdout=log,
        stderr=subprocess.STDOUT,
        start_new_session=True,
    )
    try:
        expected = NODES[profile] | {'state_publisher'}
        wait_for(
            lambda: expected <= set(ros.node.get_node_names()), 90, f'the nodes {sorted(expected)}'
        )
        got = _parameter(ros, node, name)
        if with_file:
            assert got == value, (node, name, got)
        else:
            assert got != value, (node, name, got)
        if profile == 'emulated-robot' and with_file:  # the profile's own port wins the file's
            assert _parameter(ros, 'bridge_node', 'port') == '/tmp/hexapod_radio'
        if profile == 'robot' and with_file:  # no --port given: the file's
            assert (
                _parameter(ros, 'bridge_node', 'port')
                == params['bridge_node']['ros__parameters']['port']
            )
    finally:
        code = _stop(proc, log)
    text = (tmp_path / 'launch.log').read_text()
    assert stopped(code, text), text[-3000:]
    assert 'Traceback' not in text, text[text.index('Traceback') - 200 :][:3000]


def _launcher(tmp_path, domain_id: int, *args: str, home: Path | None = None):
    """Start scripts/launch.py with ``args`` in its own session; (process, log path)."""
    path = tmp_path / f'launch_{len(list(tmp_path.glob("launch_*.log")))}.log'
    log = open(path, 'w')
    env = dict(os.environ, ROS_DOMAIN_ID=str(domain_id))
    if home is not None:
        env.update(ROS_HOME=str(home))
    proc = subprocess.Popen(
        [sys.executable, str(WS / 'scripts' / 'launch.py'), *args],
        cwd=WS,  # as a user runs it, from the repository root
        env=env,
        stdout=log,
        stderr=subprocess.STDOUT,
        start_new_session=True,
    )
    return proc, log, path


def _child(proc: subprocess.Popen, executable: str) -> int:
    """The pid of the launcher's child running ``executable``."""
    for child in Path(f'/proc/{proc.pid}/task/{proc.pid}/children').read_text().split():
        cmdline = Path(f'/proc/{child}/cmdline').read_bytes().split(b'\0')
        if any(part.endswith(executable.encode()) for part in cmdline):
            return int(child)
    raise AssertionError(f'no child process runs {executable}')


@pytest.mark.ros
@pytest.mark.parametrize('stop_all', [False, True], ids=['others-run-on', 'stop-on-exit'])
def test_a_node_that_dies_is_named_with_its_status_and_last_lines(
    ros, domain_id, tmp_path, stop_all
):
    odom = ros.collect(
        Odometry, 'odom', QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE)
    )
    extra = ['--stop-on-exit'] if stop_all else []
    proc, log, path = _launcher(tmp_path, domain_id, 'sim', '--rtf', '0', *extra)
    try:
        wait_for(lambda: odom and math_dist(odom[-1]) > 0.2, 60, 'the simulated robot walking')
        os.kill(_child(proc, 'gait_node'), signal.SIGKILL)
        said = '[launch] gait_node exited on its own, killed by SIGKILL (status 137)'
        wait_for(lambda: said in path.read_text(), 20, 'the launcher naming the dead node')
        if stop_all:
            assert proc.wait(40) == 137
        else:
            heard = len(odom)
            wait_for(lambda: len(odom) > heard + 20, 30, 'sim_node running on')
            assert proc.poll() is None
    finally:
        code = _stop(proc, log) if proc.poll() is None else proc.returncode
    text = path.read_text()
    after = text[text.index(said) :]
    assert ('stopping the others' if stop_all else 'the others keep running') in after
    assert 'Its last lines:' in after and '[launch]   | ' in after, after[:2000]
    assert code == 137, text[-3000:]


#: Every profile of scripts/launch.py, as a user starts it (the robot one against the emulator),
#: and the nodes it runs.
PROFILES = {
    'sim': (['sim', '--rtf', '0'], {'gait_node', 'sim_node', 'state_publisher'}),
    'adapt-sim': (
        ['adapt-sim', '--failed-legs', '1'],
        {'gait_node', 'sim_node', 'state_publisher', 'adapt_node'},
    ),
    'navigate-sim': (
        ['navigate-sim', '--failed-legs', '1', '2'],
        {'gait_node', 'sim_node', 'state_publisher', 'navigate_node'},
    ),
    'emulated-robot': (
        ['emulated-robot', '--archive', '--navigate'],
        {'bridge_node', 'state_publisher', 'adapt_node', 'navigate_node'},
    ),
    'robot': (
        ['robot', '--archive', '--navigate'],
        {'bridge_node', 'state_publisher', 'adapt_node', 'navigate_node'},
    ),
}


@pytest.mark.slow
@pytest.mark.ros
@pytest.mark.parametrize('profile', sorted(PROFILES))
def test_a_clean_ctrl_c_of_every_profile_logs_no_error_and_no_traceback(
    ros, domain_id, tmp_path, profile
):
    args, nodes = list(PROFILES[profile][0]), PROFILES[profile][1]
    emulator = None
    if profile == 'robot':  # the real radio's stand-in: the emulator on ports of this test's own
        radio, imu = tmp_path / 'radio', tmp_path / 'imu'
        emulator = subprocess.Popen(
            [sys.executable, '-m', 'hexapod_bridge.emulator.robot_emulator_cli', '--sim',
             '--radio-link', str(radio), '--imu-link', str(imu)],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
        )  # fmt: skip
        wait_for(lambda: radio.exists() and imu.exists(), 60, 'the emulator ports')
        args += ['--port', str(radio), '--imu-port', str(imu)]
    before = tree_state()
    proc, log, path = _launcher(tmp_path, domain_id, *args, home=tmp_path / 'ros_home')
    try:
        # every node of the profile in the graph: up (a Ctrl-C while Python still imports a node's
        # modules is Python's KeyboardInterrupt, before the node can handle it)
        wait_for(lambda: nodes <= set(ros.node.get_node_names()), 90, f'the {profile} graph up')
        time.sleep(3.0)
    finally:
        code = _stop(proc, log)
        if emulator is not None:
            emulator.send_signal(signal.SIGINT)
            emulator.wait(30)
    text = path.read_text()
    errors = [line for line in text.splitlines() if 'ERROR' in line or 'Traceback' in line]
    assert not errors, '\n'.join(errors[:20]) + '\n' + text[-3000:]
    assert stopped(code, text), text[-3000:]
    assert tree_state() == before, sorted(tree_state() ^ before)  # the source tree untouched
