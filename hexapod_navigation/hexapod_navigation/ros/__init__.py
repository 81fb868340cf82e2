# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
navigate's ROS side.

The node, its client, its messages and settings, the goals' turns and the bodies it walks
through the graph.
"""
