# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
from glob import glob

from setuptools import find_packages, setup

package_name = 'hexapod_description'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    data_files=[
        ('share/ament_index/resource_index/packages', [f'resource/{package_name}']),
        (f'share/{package_name}', ['package.xml']),
        (f'share/{package_name}/urdf', glob('urdf/*')),
        (f'share/{package_name}/launch', glob('launch/*.py')),
        # views that open ready: RViz 2 and Foxglove (docs/ros.md)
        (f'share/{package_name}/rviz', glob('rviz/*.rviz')),
        (f'share/{package_name}/foxglove', glob('foxglove/*.json')),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='Hexapod adaptation team',
    maintainer_email='hexapod-dev@example.com',
    description='URDF of the UCT RARL hexapod and a Python API to read it.',
    license='MIT',
    entry_points={'console_scripts': ['describe = hexapod_description.describe_cli:main']},
)
