# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The robot emulator's firmware (hexapod_bridge.emulator.firmware): failsafe."""

from __future__ import annotations

from hexapod_bridge.emulator.firmware import RobotFirmware


def test_failsafe_trips_without_pings():
    fw = RobotFirmware(failsafe_windows=11)
    fw.start_walk(0.0, 60.0)
    t = 0.0
    while t < 40.0 and fw.walking:
        t += 0.05
        fw.advance(t)
    assert not fw.walking and fw.stats.failsafe_trips == 1
    assert 11 * 2.5 - 0.1 <= t <= 12 * 2.5 + 0.1


def test_the_emulated_operator_puts_a_fallen_robot_back_on_its_feet(capsys):
    """--right-after: a body lying past FALLEN_TILT that long is righted; a standing one never."""
    from hexapod_bridge.emulator.robot_emulator_cli import _right_if_fallen, RIGHTED
    from hexapod_sim import create_simulator, SimConfig
    from hexapod_sim.simulator import peak_tilt
    import numpy as np

    sim = create_simulator(SimConfig(engine='mujoco'))
    try:
        standing = np.array(sim.joint_states()[0])
        assert _right_if_fallen(sim, 0.0, None, 2.0) is None
        sim.d.qpos[3:7] = [0.0, 1.0, 0.0, 0.0]  # on its back (w, x, y, z): the robot fell
        assert peak_tilt(sim.base_pose()[1]) > 3.0
        assert _right_if_fallen(sim, 10.0, None, 2.0) == 10.0  # lying since now
        assert _right_if_fallen(sim, 11.9, 10.0, 2.0) == 10.0  # not yet
        assert RIGHTED not in capsys.readouterr().out
        assert _right_if_fallen(sim, 12.0, 10.0, 2.0) is None
        assert peak_tilt(sim.base_pose()[1]) < 1e-6
        assert np.allclose(sim.joint_states()[0], standing)
        assert f'{RIGHTED}12.000' in capsys.readouterr().out
    finally:
        sim.close()
