"""The one ``main()`` every node of this workspace uses (the Jazzy pattern of ros2/demos):
spin in ``try``, treat Ctrl-C and an external shutdown (SIGTERM) as a normal exit, then let
the node release what it holds (``shutdown()`` if it has one), destroy it, shut rclpy down."""
from __future__ import annotations

import re
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
            name = re.sub(r"(?<!^)(?=[A-Z])", "_", getattr(make_node, "__name__", "node")).lower()   # SimNode -> sim_node
            print(f"[{name}] refusing to start: {exc}", file=sys.stderr)
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


def nodes_named(node: Node, fully_qualified_name: str) -> int:
    """How many nodes in the graph (this one included) carry ``fully_qualified_name``."""
    name = fully_qualified_name.rstrip("/")
    count = 0
    for other, namespace in node.get_node_names_and_namespaces():
        if f"{namespace.rstrip('/')}/{other}" == name:
            count += 1
    return count


def watch_for_duplicates(node: Node, report: Callable[[str], None], period: float = 2.0) -> None:
    """Report (once per appearance) when another node with this node's name joins the graph:
    two simulators or two adaptation servers answering the same services make clients hang."""
    state = {"reported": False}

    def check() -> None:
        count = nodes_named(node, node.get_fully_qualified_name())
        if count > 1 and not state["reported"]:
            report(f"{count} nodes named {node.get_fully_qualified_name()} are in the graph: services and topics "
                   "of that name are ambiguous; stop the extra one or start it with another name "
                   "(--ros-args -r __node:=NAME)")
        state["reported"] = count > 1

    node.create_timer(period, check)
