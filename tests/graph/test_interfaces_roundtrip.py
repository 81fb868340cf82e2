# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Every hexapod_msgs message and service type round-trips between two processes over DDS."""

from __future__ import annotations

import os
from pathlib import Path
import signal
import subprocess
import sys

from hexapod_msgs.action import Adapt, Navigate
from hexapod_msgs.msg import (
    AdaptationTrial,
    DamageDiagnosis,
    FootContacts,
    GaitParameters,
    LegDamage,
    LinkStatus,
    RobotTrial,
    ServoFailure,
    TrajectoryActivation,
)
from hexapod_msgs.srv import (
    GetLegDamage,
    GetServoFailures,
    ReportDistance,
    SetLegFailure,
    UploadGait,
)
import pytest
from rclpy.qos import QoSProfile, ReliabilityPolicy

MESSAGES = [
    GaitParameters,
    FootContacts,
    AdaptationTrial,
    LinkStatus,
    ServoFailure,
    TrajectoryActivation,
    LegDamage,
    RobotTrial,
    DamageDiagnosis,
]
SERVICES = [GetServoFailures, SetLegFailure, ReportDistance, UploadGait, GetLegDamage]
# the actions go through their servers in tests/graph (test_adapt_graph, test_navigate_graph)
ACTIONS = [Adapt, Navigate]
QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)


def _equal(a, b) -> bool:
    """Field by field (CDR bytes are no test: the alignment padding need not be zero)."""
    if hasattr(a, 'get_fields_and_field_types'):
        return type(a) is type(b) and all(
            _equal(getattr(a, f), getattr(b, f)) for f in a.get_fields_and_field_types()
        )
    if isinstance(a, (list, tuple)) or getattr(a, 'ndim', 0) > 0:
        return len(a) == len(b) and all(_equal(x, y) for x, y in zip(a, b))
    return a == b


def test_every_interface_is_covered():
    pkg = Path(__file__).resolve().parents[2] / 'hexapod_msgs'
    declared_msgs = {f.stem for f in (pkg / 'msg').glob('*.msg')}
    declared_srvs = {f.stem for f in (pkg / 'srv').glob('*.srv')}
    assert declared_msgs == {m.__name__ for m in MESSAGES}
    assert declared_srvs == {s.__name__ for s in SERVICES}
    assert {f.stem for f in (pkg / 'action').glob('*.action')} == {a.__name__ for a in ACTIONS}


@pytest.mark.ros
def test_round_trip_between_processes(ros, domain_id, tmp_path):
    from interface_fill import fill, request_seed

    from conftest import wait_for

    echo = subprocess.Popen(
        [sys.executable, str(Path(__file__).with_name('ros_echo.py'))],
        env=dict(os.environ, ROS_DOMAIN_ID=str(domain_id)),
        stdout=open(tmp_path / 'echo.log', 'w'),
        stderr=subprocess.STDOUT,
    )
    try:
        received = {m: ros.collect(m, f'rt/{m.__name__}/echo', QOS) for m in MESSAGES}
        pubs = {m: ros.node.create_publisher(m, f'rt/{m.__name__}', QOS) for m in MESSAGES}
        sent = {m: fill(m, seed=i + 11) for i, m in enumerate(MESSAGES)}
        for m, pub in pubs.items():
            wait_for(
                lambda pub=pub: pub.get_subscription_count() > 0,
                30,
                f'echo subscriber of {m.__name__}',
            )
        for m, pub in pubs.items():
            # resend until the echo arrives (discovery of the echo's publisher may lag)
            wait_for(
                lambda m=m, pub=pub: received[m] or pub.publish(sent[m]),
                20,
                f'echo of {m.__name__}',
                0.2,
            )
            assert _equal(received[m][0], sent[m]), m.__name__
        for i, srv in enumerate(SERVICES):
            request = fill(srv.Request, seed=100 + i)
            response = ros.call(srv, f'rt/{srv.__name__}', request)
            expected = fill(srv.Response, request_seed(request))
            assert _equal(response, expected), srv.__name__
    finally:
        echo.send_signal(signal.SIGINT)
        try:
            echo.wait(10)
        except subprocess.TimeoutExpired:  # never let a stuck helper fail or hang the suite
            echo.kill()
            echo.wait()
