# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
sim_node against hostile input.

Bad start-up parameters are refused in one line naming the allowed range (no traceback, exit status
2); a fuzzed stream of trajectory messages never kills it and never replaces the gait it is
playing.
"""

from __future__ import annotations

import math

from diagnostic_msgs.msg import DiagnosticStatus
import numpy as np
import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import Header
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from conftest import status_log_qos, wait_for

pytestmark = pytest.mark.ros
LATCHED = QoSProfile(
    depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE
)
JOINTS = [f'joint_{leg}_{k}' for leg in range(1, 7) for k in (1, 2, 3)]


@pytest.mark.parametrize(
    'param,value,expected',
    [
        ('friction', -1.0, 'friction out of range Min: 0.0, Max: 10.0'),
        ('real_time_factor', float('nan'), 'real_time_factor out of range Min: 0.0, Max: 100.0'),
        ('real_time_factor', 500.0, 'real_time_factor out of range Min: 0.0, Max: 100.0'),
        ('publish_period_steps', -1, 'publish_period_steps out of range. Min: 0, Max: 240'),
        ('substeps', 65, 'substeps out of range. Min: 0, Max: 64'),
        ('failed_legs', [7], 'leg 7 does not exist: legs are numbered 1..6'),
        ('failed_legs', [1, 2, 3], 'at most 2 legs can fail'),
        ('engine', 'ode', "unknown physics engine 'ode'; choose one of: pybullet, mujoco"),
    ],
)
def test_bad_start_up_parameters_refuse_to_start_in_one_line(launch, param, value, expected):
    node = launch('hexapod_sim', 'sim_node', params={param: value})
    wait_for(lambda: not node.alive(), 30, 'sim_node to refuse to start')
    assert node.proc.returncode == 2
    log = node.log()
    assert 'Traceback' not in log
    refusal = [line for line in log.splitlines() if 'refusing to start' in line]
    assert len(refusal) == 1 and expected in refusal[0] and refusal[0].startswith('[sim_node]'), (
        log
    )


def _point(seconds: float, positions) -> JointTrajectoryPoint:
    p = JointTrajectoryPoint(positions=[float(v) for v in positions])
    whole = math.floor(seconds)
    p.time_from_start.sec, p.time_from_start.nanosec = (
        int(whole),
        int(round((seconds - whole) * 1e9)) % 1_000_000_000,
    )
    return p


def _hostile(rng: np.random.Generator, k: int) -> JointTrajectory:
    """A malformed or oversized trajectory, kind k mod 8."""
    kind = k % 8
    q = rng.uniform(-1, 1, 18)
    msg = JointTrajectory(joint_names=list(JOINTS))
    if kind == 0:  # the 7.5 TiB message: two points 2^31 - 1 s apart
        msg.points = [_point(0, q), _point(2**31 - 1, q)]
    elif kind == 1:  # NaN / inf positions
        bad = q.copy()
        bad[int(rng.integers(18))] = rng.choice([np.nan, np.inf, -np.inf])
        msg.points = [_point(0, q), _point(0.1, bad)]
    elif kind == 2:  # wrong, duplicated or missing joint names
        msg.joint_names = list(rng.choice(JOINTS + ['hip', 'knee'], size=int(rng.integers(0, 20))))
        msg.points = [_point(0, q[: len(msg.joint_names)]), _point(0.1, q[: len(msg.joint_names)])]
    elif kind == 3:  # times not increasing or not starting at 0
        msg.points = [_point(float(rng.uniform(0, 5)), q), _point(float(rng.uniform(0, 0.001)), q)]
    elif kind == 4:  # ragged positions
        msg.points = [_point(0, q), _point(0.1, q[: int(rng.integers(0, 17))])]
    elif kind == 5:  # too many points
        msg.points = [_point(i * 1e-4, q) for i in range(60_001)]
    elif kind == 6:  # non-uniform spacing
        msg.points = [_point(0, q), _point(0.1, q), _point(0.5, q)]
    else:  # empty
        msg.points = []
    return msg


@pytest.mark.slow
def test_fuzzed_trajectories_never_kill_sim_node_or_replace_its_gait(ros, launch):
    sim = launch(
        'hexapod_sim', 'sim_node', params={'real_time_factor': 0.0, 'publish_period_steps': 24}
    )
    status = ros.collect(DiagnosticStatus, 'sim/status', status_log_qos())
    active = ros.collect(Header, 'sim/active_trajectory', LATCHED)
    pub = ros.node.create_publisher(JointTrajectory, 'gait/joint_trajectory', LATCHED)
    wait_for(lambda: pub.get_subscription_count() > 0, 30, 'sim_node subscription')
    # a good gait first: two points, 0.5 s cycle
    good = JointTrajectory(
        joint_names=list(JOINTS), points=[_point(0, np.zeros(18)), _point(0.25, np.zeros(18))]
    )
    good.header.stamp.sec = 4242
    pub.publish(good)

    def errors() -> list[str]:
        return [s.message for s in status if s.level == DiagnosticStatus.ERROR]

    def playing() -> bool:
        return bool(active) and active[-1].stamp.sec == 4242

    # a loaded machine (the other test process beside it) has taken over 30 s to start it
    wait_for(lambda: playing() or errors(), 90, 'the good gait, or why not')
    assert playing() and not errors(), (errors(), sim.log())
    rng = np.random.default_rng(7)
    refused = 0
    for k in range(40):
        before = len(errors())
        pub.publish(_hostile(rng, k))
        wait_for(
            lambda: len(errors()) > before,
            30,
            f'hostile trajectory {k} refused',
        )
        refused += 1
        assert sim.alive(), f'sim_node died on hostile trajectory {k}'
    said = errors()
    assert all('rejected' in m and 'previous gait kept' in m for m in said), said
    assert any('at most 60 s' in m for m in said) and any(
        'at most 60000 points' in m for m in said
    )
    assert active[-1].stamp.sec == 4242 and refused == 40  # the good gait is still the one playing
