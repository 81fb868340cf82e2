# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Making maps offline: the archive file, CVT, MAP-Elites, the simulated evaluation (ROS-free)."""
