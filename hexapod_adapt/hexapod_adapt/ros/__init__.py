# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The ROS side: adapt_node, adapt_client, the graph port the nodes share, MCAP recording."""
