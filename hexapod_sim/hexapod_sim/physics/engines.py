# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The engines behind the simulator interface: :func:`create_simulator` picks one by name.

Each engine is imported only when it is asked for (MuJoCo and DART are optional
dependencies), and the engine modules import the interface, never this module.
"""

from __future__ import annotations

from hexapod_sim.simulator import SimConfig, Simulator


def create_simulator(config: SimConfig | None = None) -> Simulator:
    """Return a simulator running the engine named in ``config`` (default: PyBullet)."""
    config = config or SimConfig()
    if config.engine == 'dart':
        # optional dependency: imported on use
        from hexapod_sim.physics.dart_engine import DartSimulator

        return DartSimulator(config)
    if config.engine == 'mujoco':
        # optional dependency: imported on use
        from hexapod_sim.physics.mujoco_engine import MujocoSimulator

        return MujocoSimulator(config)
    from hexapod_sim.physics.pybullet_engine import PyBulletSimulator

    return PyBulletSimulator(config)
