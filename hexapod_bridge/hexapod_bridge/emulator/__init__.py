# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The robot's stand-in for tests and bench work.

The firmware side of the radio protocol and an emulated Xsens IMU, optionally walking in a
simulator (hexapod_sim's interface, either engine). ``robot_emulator`` serves it on
pseudo-terminals. The host bridge library (the rest of hexapod_bridge) does not import this package
and needs no physics.
"""
