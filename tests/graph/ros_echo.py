#!/usr/bin/env python3
# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Echo process for the interface round-trip test.

For each message type, republish what arrives on rt/<Type> to rt/<Type>/echo; for each service
type, serve rt/<Type> answering fill(Response, request_seed(request)) so the caller can verify the
request arrived intact.
"""

from __future__ import annotations

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # PYTHONSAFEPATH drops it

from interface_fill import fill, request_seed  # noqa: E402
import rclpy  # noqa: E402
from rclpy.executors import ExternalShutdownException  # noqa: E402
from test_interfaces_roundtrip import MESSAGES, QOS, SERVICES  # noqa: E402


def main() -> None:
    rclpy.init()
    node = rclpy.create_node('ros_echo')
    for msg_type in MESSAGES:
        pub = node.create_publisher(msg_type, f'rt/{msg_type.__name__}/echo', QOS)
        node.create_subscription(msg_type, f'rt/{msg_type.__name__}', pub.publish, QOS)
    for srv_type in SERVICES:

        def handle(request, response, srv_type=srv_type):
            return fill(srv_type.Response, request_seed(request))

        node.create_service(srv_type, f'rt/{srv_type.__name__}', handle)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    main()
