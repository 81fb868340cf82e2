"""The one ``main()`` every node of this workspace uses (the Jazzy pattern of ros2/demos):
spin in ``try``, treat Ctrl-C and an external shutdown (SIGTERM) as a normal exit, then let
the node release what it holds (``shutdown()`` if it has one), destroy it, shut rclpy down."""
from __future__ import annotations

import sys
from typing import Callable

import rclpy
from rclpy.exceptions import InvalidParameterTypeException, InvalidParameterValueException
from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor, SingleThreadedExecutor
from rclpy.node import Node


def run_node(make_node: Callable[[], Node], args: list[str] | None = None, num_threads: int = 1) -> int:
    """Create the node after ``rclpy.init`` and spin it (multi-threaded if ``num_threads`` > 1).
    A node whose start-up parameters are unusable raises ValueError from its constructor: that
    is printed as one line and the process exits with status 2, without a traceback."""
    rclpy.init(args=args)
    node = None
    executor = MultiThreadedExecutor(num_threads=num_threads) if num_threads > 1 else SingleThreadedExecutor()
    try:
        try:
            node = make_node()
        except (ValueError, InvalidParameterValueException, InvalidParameterTypeException) as exc:
            print(f"[{getattr(make_node, '__name__', 'node')}] refusing to start: {exc}", file=sys.stderr)
            return 2
        executor.add_node(node)
        executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        if node is not None:
            shutdown = getattr(node, "shutdown", None)
            if callable(shutdown):
                shutdown()
            node.destroy_node()
        rclpy.try_shutdown()
    return 0
