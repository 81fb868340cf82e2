# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The URDF as each engine loads it agrees with the controller's kinematics and masses.

For random joint configurations, each engine's tibia frame carried to the foot
tip equals FK eqs. 3.48-3.50 placed at the leg's mount; the total mass is table 3.5's.
"""

from __future__ import annotations

from hexapod_description import load_model
from hexapod_gait import default_kinematics
from hexapod_sim import create_simulator, ENGINES, SimConfig
from hexapod_sim.simulator import quat_to_matrix
import numpy as np
import pytest

TABLE_3_5_TOTAL = 3.468  # kg


@pytest.mark.parametrize('engine', ENGINES)
def test_engine_feet_match_analytic_forward_kinematics(engine):
    model = load_model()
    kin = default_kinematics()
    a3 = model.tibia_length
    rng = np.random.default_rng(2024)
    worst = 0.0
    with create_simulator(SimConfig(engine=engine)) as sim:
        for _ in range(100):
            q = np.array([rng.uniform(lim.lower, lim.upper) for lim in model.limits])
            sim.reset(q, body_height=1.0)  # in the air: nothing pushes the joints yet
            poses = sim.link_poses()
            base_pos, base_quat = poses['base_link']
            to_base = quat_to_matrix(base_quat).T
            for leg, mount in enumerate(model.mounts, start=1):
                tibia_pos, tibia_quat = poses[f'link_{leg}_3']
                foot_world = tibia_pos + quat_to_matrix(tibia_quat) @ np.array([a3, 0.0, 0.0])
                foot = to_base @ (foot_world - base_pos)
                local = kin.forward(q[slice(3 * (leg - 1), 3 * leg)])
                c, s = np.cos(mount.yaw), np.sin(mount.yaw)
                expected = np.array(
                    [
                        mount.x + c * local[0] - s * local[1],
                        mount.y + s * local[0] + c * local[1],
                        mount.z + local[2],
                    ]
                )
                worst = max(worst, float(np.linalg.norm(foot - expected)))
    print(f'{engine}: max |foot - FK| over 100 configurations x 6 legs: {worst * 1e3:.2e} mm')
    assert worst <= 0.5e-3


@pytest.mark.parametrize('engine', ENGINES)
def test_engine_masses_match_table_3_5(engine):
    with create_simulator(SimConfig(engine=engine)) as sim:
        masses = sim.link_masses()
    assert abs(sum(masses.values()) - TABLE_3_5_TOTAL) < 0.001
    assert set(masses) == {'base_link'} | {
        f'link_{leg}_{k}' for leg in range(1, 7) for k in (1, 2, 3)
    }


def test_the_tf_chain_of_the_urdf_gives_the_kinematic_feet():
    """
    The state publisher's transforms put each foot where FK says.

    base_link -> coxa -> femur -> tibia -> foot, composed from them, lands on FK eqs. 3.48-3.50
    at the leg's mount.
    """
    from hexapod_description.tf_tree import joint_frames, moving_transforms, static_transforms

    model, kin = load_model(), default_kinematics()
    frames = joint_frames()
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(100):
        q = np.array([rng.uniform(lim.lower, lim.upper) for lim in model.limits])
        parts = moving_transforms(frames, dict(zip(model.joint_names, q))) + static_transforms(
            frames
        )
        place = {f.child: (f.parent, np.array(xyz), quat_to_matrix(r)) for f, xyz, r in parts}
        for leg, mount in enumerate(model.mounts, start=1):
            point, link = np.zeros(3), f'link_{leg}_foot'
            while link != 'base_link':  # carry the foot origin up to base_link
                parent, xyz, rot = place[link]
                point, link = rot @ point + xyz, parent
            local = kin.forward(q[slice(3 * (leg - 1), 3 * leg)])
            c, s = np.cos(mount.yaw), np.sin(mount.yaw)
            expected = np.array(
                [
                    mount.x + c * local[0] - s * local[1],
                    mount.y + s * local[0] + c * local[1],
                    mount.z + local[2],
                ]
            )
            worst = max(worst, float(np.linalg.norm(point - expected)))
    assert worst < 1e-9, worst
