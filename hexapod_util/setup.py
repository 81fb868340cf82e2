# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
from glob import glob

from setuptools import find_packages, setup

package_name = 'hexapod_util'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    data_files=[
        ('share/ament_index/resource_index/packages', [f'resource/{package_name}']),
        (f'share/{package_name}', ['package.xml']),
        (f'share/{package_name}/config', glob('config/*.xml')),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='Hexapod adaptation team',
    maintainer_email='hexapod-dev@example.com',
    description='Plumbing the hexapod packages share: ROS glue, recording, command-line helpers.',
    license='MIT',
)
