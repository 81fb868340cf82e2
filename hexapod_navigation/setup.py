# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
from glob import glob

from setuptools import find_packages, setup

package_name = 'hexapod_navigation'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    data_files=[
        ('share/ament_index/resource_index/packages', [f'resource/{package_name}']),
        (f'share/{package_name}', ['package.xml']),
        (f'share/{package_name}/launch', glob('launch/*.py')),
        (f'share/{package_name}/config', glob('config/*.yaml')),
        # the navigation repertoire, its generation log and its damage bank
        (
            f'share/{package_name}/maps',
            [m for m in glob('maps/*.npz') if not m.endswith('.ckpt.npz')]
            + glob('maps/*.log.jsonl'),
        ),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='Hexapod adaptation team',
    maintainer_email='hexapod-dev@example.com',
    description=(
        'The navigate action: a damaged hexapod walks to a goal over a repertoire of'
        ' omnidirectional steps, learning how the damage bends them.'
    ),
    license='MIT',
    entry_points={
        'console_scripts': [
            'navigate_node = hexapod_navigation.ros.navigate_node:main',
            'navigate_client = hexapod_navigation.ros.navigate_client_cli:main',
            'run_navigation = hexapod_navigation.offline.run_navigation_cli:main',
        ]
    },
)
