# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The launch files (for full ROS installs) compile; scripts/launch.py runs a graph.

scripts/launch.py starts a working graph and stops it cleanly on Ctrl-C.
"""

from __future__ import annotations

import os
from pathlib import Path
import py_compile
import signal
import subprocess
import sys

from conftest import wait_for, WS
from nav_msgs.msg import Odometry
import pytest
from rclpy.qos import QoSProfile, ReliabilityPolicy


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
    assert code == 0, text[-2000:]
    assert 'Traceback' not in text, text[text.index('Traceback') - 200 :][:3000]


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
        proc.send_signal(signal.SIGINT)
        try:
            code = proc.wait(40)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            code = None
        log.close()
    text = (tmp_path / 'launch.log').read_text()
    assert 'simulating with the mujoco engine at real_time_factor 0' in text, text[-2000:]
    assert code == 0, text[-2000:]
