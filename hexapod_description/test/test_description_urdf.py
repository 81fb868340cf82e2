# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The URDF against the thesis tables (3.4-3.9, eqs. 3.8-3.11), in PyBullet and yourdfpy.

The expected numbers are typed here from the thesis on purpose: this is the independent check
of the model, which is the only other place they appear.
"""

from __future__ import annotations

import math
from pathlib import Path
import shutil
import subprocess

from hexapod_description import load_model, urdf_path
import numpy as np
import pytest
import yourdfpy

TABLE_3_5_MASS = {'base': 1.320, 'coxa': 0.146, 'femur': 0.058, 'tibia': 0.154}
TABLE_3_6_COM = {
    'coxa': (4.992e-2, -1.400e-4, 1.457e-2),
    'femur': (5.478e-2, -3.960e-3, 0.0),
    'tibia': (3.309e-2, 7.960e-3, -2e-5),
    'base': (0.0, 0.0, -6.800e-4),
}
# (ixx, ixy, ixz, iyy, iyz, izz), eqs. 3.8-3.11
INERTIA = {
    'base': (5.255e-3, 0, -1e-11, 5.255e-3, -1.300e-10, 1.015e-2),
    'coxa': (6.023e-5, -6.480e-8, 9.306e-7, 6.045e-5, -3.629e-7, 4.573e-5),
    'femur': (3.893e-5, 1.706e-6, 0, 1.248e-4, 0, 9.600e-5),
    'tibia': (3.191e-5, 1.071e-5, -1.034e-7, 1.890e-4, 4.968e-8, 1.927e-4),
}
TABLE_3_8_LIMITS = {1: (-1.745, 1.745), 2: (-2.618, 2.269), 3: (-2.967, 2.269)}
TABLE_3_9 = {1: (3.464, 7.686), 2: (5.194, 5.289), 3: (3.464, 7.686)}  # effort N m, velocity rad/s
PART = {1: 'coxa', 2: 'femur', 3: 'tibia'}
EXPECTED_TOTAL = TABLE_3_5_MASS['base'] + 6 * (
    TABLE_3_5_MASS['coxa'] + TABLE_3_5_MASS['femur'] + TABLE_3_5_MASS['tibia']
)


@pytest.fixture(scope='module')
def urdf() -> yourdfpy.URDF:
    return yourdfpy.URDF.load(str(urdf_path()), load_meshes=False, build_scene_graph=True)


def test_total_mass_yourdfpy_and_api(urdf):
    total = sum(link.inertial.mass for link in urdf.robot.links if link.inertial is not None)
    assert abs(total - EXPECTED_TOTAL) < 0.001
    assert abs(load_model().total_mass - EXPECTED_TOTAL) < 0.001


def test_link_mass_com_and_inertia(urdf):
    links = {link.name: link for link in urdf.robot.links}
    for name, part in [('base_link', 'base')] + [
        (f'link_{leg}_{k}', PART[k]) for leg in range(1, 7) for k in (1, 2, 3)
    ]:
        inertial = links[name].inertial
        assert inertial.mass == pytest.approx(TABLE_3_5_MASS[part], abs=1e-9), name
        np.testing.assert_allclose(
            inertial.origin[:3, 3], TABLE_3_6_COM[part], atol=1e-12, err_msg=name
        )
        np.testing.assert_allclose(inertial.origin[:3, :3], np.eye(3), atol=1e-12, err_msg=name)
        ixx, ixy, ixz, iyy, iyz, izz = INERTIA[part]
        expected = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        np.testing.assert_allclose(inertial.inertia, expected, rtol=0, atol=1e-15, err_msg=name)


def test_joint_limits_effort_velocity_tables_3_8_3_9(urdf):
    joints = {j.name: j for j in urdf.robot.joints}
    for leg in range(1, 7):
        for k in (1, 2, 3):
            name = f'joint_{leg}_{k}'
            lim = joints[name].limit
            assert (lim.lower, lim.upper) == TABLE_3_8_LIMITS[k], name
            assert (lim.effort, lim.velocity) == TABLE_3_9[k], name
            assert joints[name].type == 'revolute', name


def test_joint_origins_table_3_7(urdf):
    joints = {j.name: j for j in urdf.robot.joints}
    for leg in range(1, 7):
        alpha = (leg - 1) * math.pi / 3
        coxa = joints[f'joint_{leg}_1'].origin
        np.testing.assert_allclose(
            coxa[:3, 3], [0.125 * math.cos(alpha), 0.125 * math.sin(alpha), -0.014], atol=1e-12
        )
        np.testing.assert_allclose(
            coxa[:3, :3],
            [
                [math.cos(alpha), -math.sin(alpha), 0],
                [math.sin(alpha), math.cos(alpha), 0],
                [0, 0, 1],
            ],
            atol=1e-12,
        )
        np.testing.assert_allclose(
            joints[f'joint_{leg}_2'].origin[:3, 3], [5.317e-2, 0, 0], atol=1e-12
        )
        np.testing.assert_allclose(
            joints[f'joint_{leg}_3'].origin[:3, 3], [1.019e-1, 0, 0], atol=1e-12
        )
        for k in (1, 2, 3):
            np.testing.assert_array_equal(joints[f'joint_{leg}_{k}'].axis, [0, 0, 1])


def test_names_and_order_api():
    model = load_model()
    assert model.joint_names == tuple(f'joint_{leg}_{k}' for leg in range(1, 7) for k in (1, 2, 3))
    assert model.link_lengths == pytest.approx((0.05317, 0.1019, 0.1474))
    assert {'base_link'} | {f'link_{leg}_{k}' for leg in range(1, 7) for k in (1, 2, 3)} <= set(
        model.link_masses
    )
    assert model.limit('joint_3_2').velocity == 5.289
    with pytest.raises(ValueError, match='leg must be 1..6'):
        model.leg_joint_names(7)


def test_no_ascii_looking_binary_stl():
    # PyBullet misreads binary STL whose header starts with "solid"; we ship none at all
    # (primitives only), and if meshes are added they must not have that header.
    share = Path(urdf_path()).resolve().parent.parent
    for stl in share.rglob('*.stl'):
        head = stl.read_bytes()[:80]
        assert not head.startswith(b'solid') or b'facet' in stl.read_bytes()[:400], stl


@pytest.mark.parametrize('name', ['hexapod', 'hexapod_robot'])
def test_committed_urdf_matches_xacro(name):
    xacro = shutil.which('xacro')
    assert xacro, 'xacro is a pinned dependency'
    pkg = Path(__file__).resolve().parent.parent
    expanded = subprocess.run(
        [xacro, f'urdf/{name}.urdf.xacro'], cwd=pkg, check=True, capture_output=True, text=True
    ).stdout
    assert expanded.strip() == (pkg / 'urdf' / f'{name}.urdf').read_text().strip(), (
        f'{name}.urdf is stale: in hexapod_description/ run  xacro urdf/{name}.urdf.xacro >'
        f' urdf/{name}.urdf'
    )


def test_the_robot_description_is_the_physics_model_plus_massless_sensor_frames():
    import xml.etree.ElementTree as ET

    from hexapod_description import robot_description_path

    def parts(path):
        root = ET.parse(str(path)).getroot()
        for el in root:
            el.tail = None  # the whitespace after an element is not part of it
        return {(el.tag, el.get('name')): ET.tostring(el) for el in root if el.tag != 'material'}

    model, described = parts(urdf_path()), parts(robot_description_path())
    assert all(described.get(key) == xml for key, xml in model.items())  # nothing changed
    extra = {key: xml for key, xml in described.items() if key not in model}
    assert set(extra) == {('link', 'imu_link'), ('joint', 'joint_imu')}
    imu = ET.fromstring(extra[('link', 'imu_link')])
    assert imu.find('inertial') is None and imu.find('collision') is None
    assert ET.fromstring(extra[('joint', 'joint_imu')]).find('parent').get('link') == 'base_link'


def test_parse_errors_name_what_is_missing(tmp_path):
    from hexapod_description import parse_model

    text = urdf_path().read_text().replace('name="joint_4_foot"', 'name="joint_4_toe"')
    bad = tmp_path / 'bad.urdf'
    bad.write_text(text)
    with pytest.raises(ValueError, match='joint_4_foot'):
        parse_model(bad)


def test_the_walking_speed_bound_is_the_servos_no_load_speeds_on_the_leg_levers():
    # table 3.9's velocity limits (coxa and tibia RX-28 7.686 rad/s, femur RX-64 5.289 rad/s) on
    # the longest lever of each joint to the foot (a1+a2+a3, a2+a3, a3; eq. 3.41's lengths)
    m = load_model()
    a1, a2, a3 = m.link_lengths
    expected = 7.686 * (a1 + a2 + a3) + 5.289 * (a2 + a3) + 7.686 * a3
    assert m.max_walking_speed == pytest.approx(expected)
    # far above what any gait walks (the default map's best: 0.378 m/s), far below a lost link's
    # made-up 19 m/s
    assert 3.0 < m.max_walking_speed < 6.0
