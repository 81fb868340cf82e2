# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Plumbing every hexapod package shares, and nothing else (as nav2_util is for nav2).

* ROS glue: :mod:`.ros_glue` (QoS profiles, parameter specs, the node runner, graph helpers),
  :mod:`.middleware` (the Fast DDS profile every node runs with), :mod:`.recording` (MCAP);
* command-line helpers: :mod:`.cli` (argument checks, output claims, one line per error),
  :mod:`.files` (atomic writes), :mod:`.npz` (reading files that may be damaged),
  :mod:`.processes` (worker processes that die with their parent).

It imports no other hexapod package: it is the bottom of the package graph.
"""
