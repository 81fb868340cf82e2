# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
from glob import glob

from setuptools import find_packages, setup

package_name = 'hexapod_gait'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    data_files=[
        ('share/ament_index/resource_index/packages', [f'resource/{package_name}']),
        (f'share/{package_name}', ['package.xml']),
        (f'share/{package_name}/launch', glob('launch/*.py')),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='Hexapod adaptation team',
    maintainer_email='hexapod-dev@example.com',
    description=(
        '32-parameter kinematic gait controller (ROS-free library) and the gait node publishing'
        ' joint trajectories.'
    ),
    license='MIT',
    entry_points={
        'console_scripts': [
            'gait_node = hexapod_gait.gait_node:main',
            'footfall = hexapod_gait.footfall_cli:main',
            'state_publisher = hexapod_gait.state_publisher_node:main',
        ]
    },
)
