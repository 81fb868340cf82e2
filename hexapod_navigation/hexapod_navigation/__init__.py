# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The navigate action: a damaged hexapod walks to a goal, learning how the damage bends its steps.

ROS-free library (the repertoire, the planner and its GP correction with the damage bank, the
episode loop, the experiment) beside navigate_node, navigate_client and run_navigation. Depends
on hexapod_adapt (archives, the GP mixture), never the other way.
"""
