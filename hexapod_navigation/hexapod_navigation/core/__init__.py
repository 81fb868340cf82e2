# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
What navigate does, ROS-free.

The repertoire, its learned correction and damage bank, the planner, the episode loop.
"""
