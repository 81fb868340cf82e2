# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The Fast DDS profile: a service waits for a client discovered late instead of dropping its answer.

A lost answer was seen in CI (bridge_node's ~/arm called just after the node started: "failed to
send response (timeout)"). It cannot be provoked at will, so these tests pin down the mechanism:
a client whose reply reader the service never discovers (its reply QoS is incompatible) makes the
service wait the profile's 2 s per answer, against Fast DDS's 100 ms without the profile.
"""

from __future__ import annotations

import os
from pathlib import Path
import subprocess
import sys
import time

from hexapod_util.middleware import fastdds_profile_path, profile_environment, PROFILES_ENV
import pytest

from conftest import next_domain, RosHarness, wait_for, WS

SERVER = """
import sys, time, rclpy
from std_srvs.srv import Trigger
rclpy.init()
node = rclpy.create_node('profile_probe')
def answer(request, response):
    print('callback', time.monotonic(), flush=True)
    response.success = True
    return response
node.create_service(Trigger, sys.argv[1], answer)
print('ready', flush=True)
rclpy.spin(node)
"""


def test_the_profile_environment_names_the_shipped_file_and_keeps_a_users_choice():
    path = Path(profile_environment({})[PROFILES_ENV])
    assert path == fastdds_profile_path() and path.is_file()
    assert 'profile_name="service"' in path.read_text()
    assert profile_environment({PROFILES_ENV: '/etc/my_profile.xml'}) == {}


@pytest.mark.parametrize('preset', ['', '/etc/my_profile.xml'])
def test_env_sh_sets_the_profile_unless_one_is_set(preset):
    env = {k: v for k, v in os.environ.items() if k != PROFILES_ENV}
    if preset:
        env[PROFILES_ENV] = preset
    out = subprocess.run(
        ['bash', '-c', f'source scripts/env.sh >/dev/null && echo "${PROFILES_ENV}"'],
        cwd=WS,
        env=env,
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()
    assert out == (preset or str(WS / 'hexapod_util' / 'config' / 'fastdds.xml'))


def _answer_spacing(ros, tmp_path: Path, with_profile: bool) -> float:
    """Seconds between the service's first two callbacks, for requests it cannot answer."""
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from std_srvs.srv import Trigger

    env = {k: v for k, v in os.environ.items() if k != PROFILES_ENV}
    if with_profile:
        env.update(profile_environment(env))
    service = f'profile_probe_{int(with_profile)}'
    log = (tmp_path / f'{service}.log').open('w+')
    server = subprocess.Popen(
        [sys.executable, '-c', SERVER, service], stdout=log, stderr=subprocess.STDOUT, env=env
    )
    try:
        wait_for(lambda: 'ready' in Path(log.name).read_text(), 30, 'the service to start')
        # Requests reach the service once it is discovered; its answers never reach this client
        # (a volatile reply writer cannot serve a transient-local reader), so the service waits
        # out max_blocking_time on each before it takes the next request.
        deaf = QoSProfile(
            depth=10,
            durability=DurabilityPolicy.TRANSIENT_LOCAL,
            reliability=ReliabilityPolicy.RELIABLE,
        )
        client = ros.node.create_client(Trigger, service, qos_profile=deaf)

        def callbacks():
            lines = Path(log.name).read_text().splitlines()
            return [float(line.split()[1]) for line in lines if line.startswith('callback ')]

        # requests sent before discovery are lost: send until one arrives, then one more
        deadline = time.monotonic() + 30
        while not callbacks():
            assert time.monotonic() < deadline, 'no request reached the service in 30 s'
            client.call_async(Trigger.Request())
            time.sleep(0.5)
            assert server.poll() is None, Path(log.name).read_text()
        client.call_async(Trigger.Request())
        first, second = wait_for(
            lambda: callbacks()[:2] if len(callbacks()) >= 2 else None,
            30,
            'a second request to reach the service',
        )
        return second - first
    finally:
        server.kill()
        server.wait()
        log.close()


def test_a_service_waits_for_a_client_discovered_late_only_with_the_profile(ros, tmp_path):
    with_profile = _answer_spacing(ros, tmp_path, with_profile=True)
    without = _answer_spacing(ros, tmp_path, with_profile=False)
    print(f'answer spacing: {with_profile:.3f} s with the profile, {without:.3f} s without')
    assert with_profile >= 1.5, f'the profile did not take effect ({with_profile:.2f} s)'
    # relative, so that a loaded machine's delays, which both runs share, cannot fail it
    assert without < with_profile - 1.0, f'Fast DDS waited {without:.2f} s without the profile'


def _wait_behind_deaf_clients(tmp_path, own_profile: bool) -> float:
    """How long gait_node's answer waits behind two requests of a client it cannot answer."""
    from rcl_interfaces.srv import GetParameters
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    ros = RosHarness(next_domain())  # a graph of its own: no killed node's endpoints linger
    env = {k: v for k, v in os.environ.items() if k != PROFILES_ENV}
    env['ROS_DOMAIN_ID'] = str(ros.domain_id)
    if own_profile:  # a user's profile without the 'service' entry: Fast DDS's 100 ms
        (tmp_path / 'own.xml').write_text(
            '<?xml version="1.0" encoding="UTF-8"?>\n'
            '<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles"><profiles/></dds>\n'
        )
        env[PROFILES_ENV] = str(tmp_path / 'own.xml')
    exe = WS / 'install' / 'hexapod_gait' / 'lib' / 'hexapod_gait' / 'gait_node'
    with (tmp_path / f'gait_node_{own_profile}.log').open('w') as log:
        node = subprocess.Popen([str(exe)], stdout=log, stderr=subprocess.STDOUT, env=env)
    try:
        good = ros.node.create_client(GetParameters, 'gait_node/get_parameters')
        assert good.wait_for_service(timeout_sec=30)
        deaf = ros.node.create_client(
            GetParameters,
            'gait_node/get_parameters',
            qos_profile=QoSProfile(
                depth=10,
                durability=DurabilityPolicy.TRANSIENT_LOCAL,
                reliability=ReliabilityPolicy.RELIABLE,
            ),
        )
        time.sleep(1.0)  # the deaf client's requests are discovered too
        deaf.call_async(GetParameters.Request(names=['x']))
        deaf.call_async(GetParameters.Request(names=['x']))
        time.sleep(0.05)
        t0 = time.monotonic()
        # gait_node's one executor thread answers in turn: after two unanswerable requests
        answer = good.call_async(GetParameters.Request(names=['x']))
        wait_for(answer.done, 30, "gait_node's answer")
        waited = time.monotonic() - t0
        return waited
    finally:
        node.kill()
        node.wait()
        ros.close()


@pytest.mark.slow
@pytest.mark.ros
def test_a_node_started_without_the_variable_uses_the_profile_unless_one_is_set(tmp_path):
    """run_node sets the profile itself, so `ros2 run` on a full install gets it too."""
    own = _wait_behind_deaf_clients(tmp_path, own_profile=True)
    ours = _wait_behind_deaf_clients(tmp_path, own_profile=False)
    print(f"answer waited {ours:.2f} s with our profile, {own:.2f} s with a user's own")
    assert ours >= 3.0, ours  # 2 x 2 s
    # relative, so that a loaded machine's delays, which both runs share, cannot fail it
    assert own < ours - 2.0, (own, ours)
