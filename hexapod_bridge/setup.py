# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
from glob import glob

from setuptools import find_packages, setup

package_name = 'hexapod_bridge'

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
        'Serial bridge to the real hexapod (433 MHz radio link and Xsens IMU), protocol library'
        ' and robot emulator.'
    ),
    license='MIT',
    entry_points={
        'console_scripts': [
            'bridge_node = hexapod_bridge.bridge_node:main',
            'robot_emulator = hexapod_bridge.emulator.robot_emulator_cli:main',
            'firmware_fuzz = hexapod_bridge.emulator.firmware_fuzz_cli:main',
            'leg_check = hexapod_bridge.leg_check_cli:main',
        ]
    },
)
