# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
from glob import glob

from setuptools import find_packages, setup

package_name = 'hexapod_adapt'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    data_files=[
        ('share/ament_index/resource_index/packages', [f'resource/{package_name}']),
        (f'share/{package_name}', ['package.xml']),
        (f'share/{package_name}/launch', glob('launch/*.py')),
        (f'share/{package_name}/config', glob('config/*.yaml')),
        # the shipped maps with their generation logs (plot_map draws them), not a checkpoint
        (
            f'share/{package_name}/maps',
            [m for m in glob('maps/*.npz') if not m.endswith('.ckpt.npz')]
            + glob('maps/*.log.jsonl'),
        ),
        # the default map's cached ceilings (hexapod_adapt.online.ceiling; maps/make_ceilings.sh)
        (f'share/{package_name}/maps/ceilings', glob('maps/ceilings/*.zip')),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='Hexapod adaptation team',
    maintainer_email='hexapod-dev@example.com',
    description=(
        'MAP-Elites map generation and map-based Bayesian optimisation (M-BOA) adaptation for the'
        ' hexapod.'
    ),
    license='MIT',
    entry_points={
        'console_scripts': [
            'generate_map = hexapod_adapt.mapping.generate_map_cli:main',
            'plot_map = hexapod_adapt.mapping.plot_map_cli:main',
            'run_experiment = hexapod_adapt.online.run_experiment_cli:main',
            'adapt_node = hexapod_adapt.ros.adapt_node:main',
            'adapt_client = hexapod_adapt.ros.adapt_client_cli:main',
            'recover_recording = hexapod_adapt.ros.recover_recording_cli:main',
            'report_distance = hexapod_adapt.ros.report_distance_cli:main',
            'adapt_service = hexapod_adapt.ros.adapt_service_cli:main',
        ]
    },
)
