# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
from glob import glob

from setuptools import find_packages, setup

package_name = 'hexapod_sim'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    data_files=[
        ('share/ament_index/resource_index/packages', [f'resource/{package_name}']),
        (f'share/{package_name}', ['package.xml']),
        (f'share/{package_name}/launch', glob('launch/*.py')),
        (f'share/{package_name}/config', glob('config/*.yaml')),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='Hexapod adaptation team',
    maintainer_email='hexapod-dev@example.com',
    description=(
        'Simulator of the hexapod behind one interface with PyBullet and MuJoCo engines, gait'
        ' evaluation, failure scenarios, and the sim node.'
    ),
    license='MIT',
    entry_points={
        'console_scripts': [
            'sim_node = hexapod_sim.sim_node:main',
            'render_walk = hexapod_sim.render_walk_cli:main',
            'fidelity_table = hexapod_sim.fidelity_table_cli:main',
        ]
    },
)
