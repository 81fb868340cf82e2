"""The URDF (in PyBullet) and the gait controller's kinematics agree: for random joint
configurations, PyBullet's foot frame equals FK eqs. 3.48-3.50 placed at each leg's mount."""
from __future__ import annotations

import numpy as np
import pybullet as p

from hexapod_description import load_model, urdf_path
from hexapod_gait import default_kinematics


def test_pybullet_feet_match_analytic_forward_kinematics():
    model = load_model()
    kin = default_kinematics()
    client = p.connect(p.DIRECT)
    try:
        body = p.loadURDF(str(urdf_path()), useFixedBase=True, physicsClientId=client)
        index = {p.getJointInfo(body, i, physicsClientId=client)[1].decode(): i
                 for i in range(p.getNumJoints(body, physicsClientId=client))}
        rng = np.random.default_rng(2024)
        worst = 0.0
        for _ in range(250):
            q = np.array([rng.uniform(lim.lower, lim.upper) for lim in model.limits])
            for name, value in zip(model.joint_names, q):
                p.resetJointState(body, index[name], value, physicsClientId=client)
            for leg, mount in enumerate(model.mounts, start=1):
                foot = p.getLinkState(body, index[f"joint_{leg}_foot"], computeForwardKinematics=True,
                                      physicsClientId=client)[4]
                local = kin.forward(q[3 * (leg - 1): 3 * leg])
                c, s = np.cos(mount.yaw), np.sin(mount.yaw)
                expected = np.array([mount.x + c * local[0] - s * local[1],
                                     mount.y + s * local[0] + c * local[1], mount.z + local[2]])
                worst = max(worst, float(np.linalg.norm(np.array(foot) - expected)))
        print(f"max |PyBullet foot - FK| over 250 configurations x 6 legs: {worst * 1e3:.2e} mm")
        assert worst <= 0.5e-3
    finally:
        p.disconnect(client)
