# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
sim_node + gait_node in separate processes (fast mode).

Trials through the ROS graph give the library's speeds; bad requests get clear errors and the node
keeps running.
"""

from __future__ import annotations

import math
import time

from diagnostic_msgs.msg import DiagnosticStatus
from hexapod_gait import from_genotype, preset
from hexapod_gait.ros_conversions import gait_to_msg
from hexapod_msgs.msg import GaitParameters as GaitParametersMsg
from hexapod_msgs.msg import LegDamage
from hexapod_msgs.srv import GetLegDamage, SetLegFailure
from hexapod_sim import create_simulator, evaluate_gait, FAILURE_POSE, SimConfig
from hexapod_sim.damage import standing_pose
from hexapod_sim.sampling import random_reachable_genotypes
from nav_msgs.msg import Odometry
import numpy as np
import pytest
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    qos_profile_sensor_data,
    QoSProfile,
    ReliabilityPolicy,
)
from sensor_msgs.msg import JointState
from std_msgs.msg import Header
from std_srvs.srv import Trigger
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from conftest import status_log_qos, wait_for

pytestmark = pytest.mark.ros
LATCHED = QoSProfile(
    depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE
)
ODOM_QOS = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE)
TRIAL = 5.0


def _ns(stamp) -> int:
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def _gaits_with_library_speeds(n_random: int, config: SimConfig) -> list[tuple[object, float]]:
    """
    Presets plus random reachable gaits that move (|speed| >= 0.03 m/s).

    With the library's speed for each (same engine as sim_node's, collisions not fatal like
    the node).
    """
    chosen = []
    with create_simulator(config) as sim:
        for name in ('tripod', 'wave', 'quadruped'):
            gait = preset(name)
            chosen.append((gait, evaluate_gait(gait, sim, collisions_fatal=False).speed))
        for genes in random_reachable_genotypes(80, seed=21):
            gait = from_genotype(genes)
            speed = evaluate_gait(gait, sim, collisions_fatal=False).speed
            if abs(speed) >= 0.03:
                chosen.append((gait, speed))
            if len(chosen) == 3 + n_random:
                break
    return chosen


@pytest.mark.slow
@pytest.mark.parametrize(
    'engine,substeps,n_random',
    [('pybullet', 0, 18), ('mujoco', 0, 10), ('mujoco', 4, 5), ('dart', 0, 3)],
)
def test_graph_trials_match_library_speeds(ros, launch, engine, substeps, n_random):
    """sim_node's ``substeps`` (0: the engine's default) runs the library's engine at them."""
    config = SimConfig(engine=engine)
    gaits = _gaits_with_library_speeds(
        n_random, config.with_substeps(substeps) if substeps else config
    )
    assert len(gaits) == 3 + n_random
    params = {'real_time_factor': 0.0, 'publish_period_steps': 24, 'engine': engine}
    sim = launch('hexapod_sim', 'sim_node', params={**params, 'substeps': substeps})
    gait_node = launch('hexapod_gait', 'gait_node', params={'initial_preset': ''})
    odom = ros.collect(Odometry, 'odom', ODOM_QOS)
    active = ros.collect(Header, 'sim/active_trajectory', LATCHED)
    resets = ros.collect(Header, 'sim/last_reset', LATCHED)
    pub = ros.node.create_publisher(GaitParametersMsg, 'gait/parameters', LATCHED)
    wait_for(lambda: pub.get_subscription_count() > 0, 30, 'gait_node subscription')
    wait_for(lambda: resets, 30, 'sim_node start-up')

    worst, repeats = 0.0, 0

    def graph_trial(i: int, gait) -> float | None:
        """One trial through the graph; None if an odometry sample it needs was lost."""
        msg = gait_to_msg(gait)
        msg.header.stamp.sec, msg.header.stamp.nanosec = 1000 + i, 0
        pub.publish(msg)
        # 1. the simulator plays the new gait (no race between "new gait" and "reset")
        wait_for(
            lambda: active and active[-1].stamp.sec == 1000 + i, 30, f'gait {i} active in sim_node'
        )
        previous_reset = _ns(resets[-1].stamp)
        # 2. reset: origin, phase 0
        assert ros.call(Trigger, 'sim_node/reset', Trigger.Request()).success
        wait_for(lambda: _ns(resets[-1].stamp) > previous_reset, 10, 'reset stamp')
        t0 = _ns(resets[-1].stamp)
        # 3. odometry over exactly TRIAL seconds of sim time
        end = t0 + int(TRIAL * 1e9)
        wait_for(
            lambda: odom and _ns(odom[-1].header.stamp) >= end,
            60,
            f'{TRIAL} s of odometry for gait {i}',
        )
        by_stamp = {_ns(o.header.stamp): o for o in list(odom)}
        start_msg = by_stamp.get(t0)
        end_msg = next((o for s, o in by_stamp.items() if abs(s - end) < 1000), None)
        if start_msg is None or end_msg is None:
            return None  # a sample was lost in transport: the trial must be repeated
        dx = end_msg.pose.pose.position.x - start_msg.pose.pose.position.x
        dy = end_msg.pose.pose.position.y - start_msg.pose.pose.position.y
        return (dx * math.cos(gait.crab_angle) + dy * math.sin(gait.crab_angle)) / TRIAL

    for i, (gait, library_speed) in enumerate(gaits):
        graph_speed = graph_trial(i, gait)
        while graph_speed is None and repeats < 5:
            repeats += 1
            graph_speed = graph_trial(100 + i + repeats, gait)
        assert graph_speed is not None, 'odometry samples kept getting lost'
        error = abs(graph_speed - library_speed) / abs(library_speed)
        worst = max(worst, error)
        assert error <= 0.02, (
            f'gait {i}: graph {graph_speed:.5f} m/s vs library {library_speed:.5f} m/s'
        )
    print(
        f'{engine}: {len(gaits)} gaits through the graph: worst relative speed error {worst:.2e}; '
        f'trials repeated for lost odometry samples: {repeats}'
    )
    assert sim.alive() and gait_node.alive()


def test_sim_node_refuses_bad_requests_and_keeps_running(ros, launch):
    sim = launch('hexapod_sim', 'sim_node', params={'real_time_factor': 0.0, 'failed_legs': [3]})
    status = ros.collect(DiagnosticStatus, 'sim/status', status_log_qos())
    joints = ros.collect(JointState, 'joint_states', qos_profile_sensor_data)
    wait_for(lambda: joints, 30, 'joint_states')
    # initially failed leg 3 is held in the failure pose
    wait_for(
        lambda: np.allclose(joints[-1].position[6:9], FAILURE_POSE, atol=0.05),
        20,
        'leg 3 in failure pose',
    )

    for legs, expected in [
        ([7], 'leg 7 does not exist'),
        ([1, 2, 3], 'at most 2 legs'),
        ([0], 'leg 0'),
    ]:
        response = ros.call(
            SetLegFailure, 'sim_node/set_leg_failure', SetLegFailure.Request(failed_legs=legs)
        )
        assert not response.success and expected in response.message
        assert list(response.failed_legs) == [3]  # nothing changed
    response = ros.call(
        SetLegFailure, 'sim_node/set_leg_failure', SetLegFailure.Request(failed_legs=[1, 4])
    )
    assert response.success and list(response.failed_legs) == [1, 4]
    wait_for(
        lambda: np.allclose(joints[-1].position[0:3], FAILURE_POSE, atol=0.05),
        20,
        'leg 1 in failure pose',
    )
    # the damage types beyond the thesis's, and their refusals
    damage = ros.collect(LegDamage, 'sim/damage', LATCHED)
    wait_for(lambda: damage and damage[-1].label == 'legs 1+4 lifted', 20, 'sim/damage latched')
    for request, expected in [
        (SetLegFailure.Request(failed_legs=[2], kinds=['broken']), "unknown damage kind 'broken'"),
        (SetLegFailure.Request(failed_legs=[2, 5], kinds=['weak']), '1 damage kinds for 2 legs'),
        (SetLegFailure.Request(failed_legs=[2], kinds=['weak'], strengths=[2.0]), '[0.05, 0.95]'),
        (
            SetLegFailure.Request(failed_legs=[2], kinds=['unpowered'], joints=['knee']),
            "got ['knee']",
        ),
        (SetLegFailure.Request(failed_legs=[2], kinds=['unpowered']), 'names its dead joints'),
        (SetLegFailure.Request(failed_legs=[1, 2, 3]), 'at most 2 legs'),
        (
            SetLegFailure.Request(failed_legs=[2], kinds=['shortened'], strengths=[0.05]),
            '[0.2, 0.9]',
        ),
    ]:
        response = ros.call(SetLegFailure, 'sim_node/set_leg_failure', request)
        assert not response.success and expected in response.message, response.message
        assert response.damage == 'legs 1+4 lifted'  # nothing changed
    response = ros.call(
        SetLegFailure,
        'sim_node/set_leg_failure',
        SetLegFailure.Request(failed_legs=[2, 5], kinds=['locked', 'weak'], strengths=[0.0, 0.5]),
    )
    assert response.success and response.damage == 'leg 2 locked, leg 5 weak 0.50'
    assert list(response.failed_legs) == [2, 5]
    wait_for(lambda: damage[-1].label == response.damage, 20, 'sim/damage after the change')
    assert list(damage[-1].kinds) == ['locked', 'weak'] and list(damage[-1].strengths) == [1, 0.5]
    now = ros.call(GetLegDamage, 'sim_node/get_damage', GetLegDamage.Request()).damage
    assert now.label == response.damage and list(now.failed_legs) == [2, 5]
    assert list(now.kinds) == ['locked', 'weak'] and list(now.strengths) == [1, 0.5]
    wait_for(
        lambda: np.allclose(joints[-1].position[3:6], standing_pose()[3:6], atol=0.08),
        20,
        'leg 2 locked in the standing pose',
    )
    # a dead femur servo: leg 3's live coxa and tibia fold, its femur hangs free
    response = ros.call(
        SetLegFailure,
        'sim_node/set_leg_failure',
        SetLegFailure.Request(
            failed_legs=[3, 6], kinds=['unpowered', 'shortened'], joints=['femur', '']
        ),
    )
    assert response.success, response.message
    assert response.damage == 'leg 3 unpowered femur, leg 6 shortened 0.50'
    wait_for(lambda: damage[-1].label == response.damage, 20, 'sim/damage after the change')
    assert list(damage[-1].joints) == ['femur', ''] and list(damage[-1].strengths) == [1, 0.5]
    wait_for(
        lambda: (
            abs(joints[-1].position[8] - FAILURE_POSE[2]) < 0.05
            and joints[-1].position[7] < FAILURE_POSE[1] - 0.5
        ),
        20,
        'leg 3 folded by its live tibia, its femur not held up',
    )

    pub = ros.node.create_publisher(JointTrajectory, 'gait/joint_trajectory', LATCHED)
    wait_for(lambda: pub.get_subscription_count() > 0, 20, 'sim_node trajectory subscription')
    pub.publish(
        JointTrajectory(joint_names=[f'joint_{leg}_{k}' for leg in range(1, 7) for k in (1, 2, 3)])
    )
    wait_for(
        lambda: status and 'at least 2 points' in status[-1].message,
        20,
        'empty trajectory refused',
    )
    assert status[-1].level == DiagnosticStatus.ERROR
    bad_names = JointTrajectory(
        joint_names=['hip', 'knee'],
        points=[
            JointTrajectoryPoint(positions=[0.0, 0.0]),
            JointTrajectoryPoint(positions=[0.0, 0.0]),
        ],
    )
    bad_names.points[1].time_from_start.nanosec = 4_166_667
    pub.publish(bad_names)
    wait_for(lambda: 'joint names must be' in status[-1].message, 20, 'wrong joint names refused')
    assert ros.call(Trigger, 'sim_node/reset', Trigger.Request()).success
    assert sim.alive()


def test_clock_is_published_at_its_period_and_never_behind_the_state(ros, launch):
    """/clock every clock_period_steps steps (and with each state message), stamps in step."""
    from rosgraph_msgs.msg import Clock

    launch(
        'hexapod_sim',
        'sim_node',
        params={'real_time_factor': 1.0, 'publish_period_steps': 24, 'clock_period_steps': 10},
    )
    reliable = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
    clocks = ros.collect(Clock, '/clock', reliable)
    odom = ros.collect(Odometry, 'odom', reliable)
    wait_for(lambda: len(odom) >= 30, 60, 'odometry')  # 3 s at real time

    def seconds(t) -> float:
        return t.sec + t.nanosec * 1e-9

    # the two topics arrive independently (and keep arriving): states first, ticks a moment later
    states = {round(seconds(m.header.stamp) * 240) for m in list(odom)}
    time.sleep(0.5)
    ticks = sorted({round(seconds(c.clock) * 240) for c in list(clocks)})
    # every tick is a multiple of 10 steps or of 24 (the state's), and every state has its tick
    assert ticks and all(t % 10 == 0 or t % 24 == 0 for t in ticks)
    within = {t for t in states if ticks[0] <= t <= ticks[-1]}  # both topics subscribed
    assert len(within) >= 20 and within <= set(ticks)
    steps = ticks[-1] - ticks[0]
    expected = steps // 10 + steps // 24 - steps // 120  # both periods, shared ticks once
    assert abs(len(ticks) - expected) <= 3
