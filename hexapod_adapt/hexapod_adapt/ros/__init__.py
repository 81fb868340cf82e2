# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The ROS side: adapt_node, adapt_client, and what other nodes use of it (exported here).

The graph port (trials through sim_node or bridge_node), the recorded topics and a run's MCAP
recording; navigate_node walks its steps through them.
"""

from hexapod_adapt.ros.graph_port import (
    GraphPort,
    RECORDED_TYPES,
    RecordedTopics,
    stamp_ns,
)
from hexapod_adapt.ros.run_recording import RunRecording
from hexapod_adapt.ros.servo_reports import ServoReports

__all__ = [
    'GraphPort',
    'RECORDED_TYPES',
    'RecordedTopics',
    'RunRecording',
    'ServoReports',
    'stamp_ns',
]
