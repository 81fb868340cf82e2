"""The one ``main()`` every node of this workspace uses (the Jazzy pattern of ros2/demos):
spin in ``try``, treat Ctrl-C and an external shutdown (SIGTERM) as a normal exit, then let
the node release what it holds (``shutdown()`` if it has one), destroy it, shut rclpy down."""
from __future__ import annotations

from typing import Callable

import rclpy
from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor, SingleThreadedExecutor
from rclpy.node import Node


def run_node(make_node: Callable[[], Node], args: list[str] | None = None, num_threads: int = 1) -> int:
    """Create the node after ``rclpy.init`` and spin it (multi-threaded if ``num_threads`` > 1)."""
    rclpy.init(args=args)
    node = None
    executor = MultiThreadedExecutor(num_threads=num_threads) if num_threads > 1 else SingleThreadedExecutor()
    try:
        node = make_node()
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
