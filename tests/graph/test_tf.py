# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The robot can be seen moving.

sim_node puts odom -> base_link on /tf, the state publisher puts every leg link on /tf and the foot
and IMU frames on /tf_static, and the URDF is on a latched robot_description -- what RViz and
Foxglove need.
"""

from __future__ import annotations

from hexapod_description import load_model
from hexapod_util.ros_glue import LATCHED, TF_QOS
import numpy as np
import pytest
from std_msgs.msg import String
from tf2_msgs.msg import TFMessage

from conftest import wait_for

pytestmark = pytest.mark.ros
LEG_LINKS = {f'link_{leg}_{k}' for leg in range(1, 7) for k in (1, 2, 3)}
FEET = {f'link_{leg}_foot' for leg in range(1, 7)}


def test_tf_tree_and_robot_description_reach_a_subscriber(ros, launch):
    launch('hexapod_sim', 'sim_node', params={'real_time_factor': 0.0, 'publish_period_steps': 24})
    launch('hexapod_gait', 'state_publisher', params={'use_sim_time': True})
    tf = ros.collect(TFMessage, '/tf', TF_QOS)
    static = ros.collect(TFMessage, '/tf_static', LATCHED)
    description = ros.collect(String, 'robot_description', LATCHED)

    def children(messages) -> dict:
        return {t.child_frame_id: t for m in list(messages) for t in m.transforms}

    wait_for(
        lambda: LEG_LINKS | {'base_link'} <= set(children(tf)),
        30,
        'odom->base_link and every leg link on /tf',
    )
    wait_for(
        lambda: FEET | {'imu_link'} <= set(children(static)),
        30,
        'the foot and IMU frames on /tf_static',
    )
    assert children(static)['imu_link'].header.frame_id == 'base_link'
    wait_for(lambda: description, 30, 'a latched robot_description')
    assert '<robot name="hexapod">' in description[0].data
    seen = children(tf)
    assert seen['base_link'].header.frame_id == 'odom'
    for link in LEG_LINKS:
        leg, k = link.split('_')[1:]
        assert seen[link].header.frame_id == (
            'base_link' if k == '1' else f'link_{leg}_{int(k) - 1}'
        )
    mount = load_model().mounts[0]
    t = seen['link_1_1'].transform.translation
    np.testing.assert_allclose([t.x, t.y, t.z], [mount.x, mount.y, mount.z], atol=1e-12)
    # stamps are sim_node's clock: the base and the legs come with the same sim-time stamps
    stamps = {(m.transforms[0].header.stamp.sec, m.transforms[0].header.stamp.nanosec) for m in tf}
    assert all(sec < 10_000 for sec, _ in stamps)
