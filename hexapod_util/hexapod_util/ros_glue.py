# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The ROS glue every node of this workspace shares, in one place:.

* the QoS profile of each topic family, one definition used by publishers and subscribers
  alike (a mismatch between the two ends is silent in DDS);
* the status helper: a node's events as ``diagnostic_msgs/DiagnosticStatus`` and in its log;
* ``run_node``, the one ``main()`` of every node (the Jazzy pattern of ros2/demos: spin in
  ``try``, Ctrl-C and an external shutdown (SIGTERM) are a normal exit, then the node releases
  what it holds (``shutdown()`` if it has one), is destroyed, rclpy shut down; start-up
  parameters it cannot use are one line and exit status 2);
* the check for a second node of the same name in the graph.
"""

from __future__ import annotations

from dataclasses import dataclass
import enum
import faulthandler
import os
import re
import signal
import sys
import threading
import time
from typing import Any, Callable, Sequence

from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
from geometry_msgs.msg import TransformStamped
from hexapod_util import guarded_logging
from hexapod_util.middleware import profile_environment
from nav_msgs.msg import Odometry
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
import rclpy
from rclpy._rclpy_pybind11 import InvalidHandle, RCLError
from rclpy.exceptions import InvalidParameterTypeException, InvalidParameterValueException
from rclpy.executors import (
    ExternalShutdownException,
    MultiThreadedExecutor,
    SingleThreadedExecutor,
)
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    qos_profile_sensor_data,
    QoSProfile,
    ReliabilityPolicy,
)
from rclpy.signals import SignalHandlerOptions

#: Latched state: the last message is kept for late joiners (gait parameters, the active
#: trajectory, reset stamps, status topics on the publishing side).
LATCHED = QoSProfile(
    depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE
)
#: A latched status topic read as a log: a depth-1 *reader* lets a status be overwritten by the
#: next one before the executor takes it (two statuses 20 ms apart were lost that way in CI).
STATUS_LOG = QoSProfile(
    depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE
)
#: Odometry: trials read it at exact instants (reset, reset + 5 s). In fast mode sim_node sends
#: ~1000 messages per wall second and a loaded subscriber can lag hundreds behind; a reliable
#: writer only re-sends what is still in its history, so keep ~5 s of it (KEEP_ALL would make
#: publish block and then fail when a subscriber stalls).
ODOM = QoSProfile(
    history=HistoryPolicy.KEEP_LAST, depth=5000, reliability=ReliabilityPolicy.RELIABLE
)
#: Poses read for the newest one (navigation): the last few only, so that a reader that falls
#: behind skips stale poses instead of working through a backlog of thousands.
POSES = QoSProfile(
    history=HistoryPolicy.KEEP_LAST, depth=10, reliability=ReliabilityPolicy.RELIABLE
)
#: Events a late joiner must still see (servo-failure reports): reliable, the last 64 kept.
EVENTS = QoSProfile(
    depth=64, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE
)
#: An action's goal, cancel and result services, on both ends: the services' default keeps only
#: the last 10 requests (or responses) not yet taken, so a burst of goals lost some (a storm of 50
#: goals in a second lost 37 result responses at a default client).
ACTION_SERVICES = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
#: An action server's or client's keyword arguments that give all three services ACTION_SERVICES.
ACTION_QOS = {
    'goal_service_qos_profile': ACTION_SERVICES,
    'result_service_qos_profile': ACTION_SERVICES,
    'cancel_service_qos_profile': ACTION_SERVICES,
}
#: Sensor streams (joint states, IMU, foot contacts): best effort, latest wins.
SENSOR = qos_profile_sensor_data
#: adapt/trials: one message per trial, reliable, the last 10 kept for a slow reader.
TRIALS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
#: /tf as tf2's broadcasters publish it.
TF_QOS = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)


def odom_transform(odom: Odometry) -> TransformStamped:
    """Return the odometry's pose as the odom -> base_link transform (REP 105), same stamp."""
    t = TransformStamped()
    t.header = odom.header
    t.child_frame_id = odom.child_frame_id
    p, q = odom.pose.pose.position, odom.pose.pose.orientation
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = p.x, p.y, p.z
    t.transform.rotation = q
    return t


@dataclass(frozen=True)
class ParamSpec:
    """One node parameter: declared from this, and listed by ``<node> --help``."""

    name: str
    default: Any  # a value, or a rclpy Parameter.Type for "no default"
    description: str  # with units
    read_only: bool = False
    range: tuple[float, float] | None = None  # noqa: A003 (inclusive; IntegerRange for ints)

    def descriptor(self) -> ParameterDescriptor:
        """Build the ROS parameter descriptor: description, read-only flag and range."""
        d = ParameterDescriptor(description=self.description, read_only=self.read_only)
        if self.range is not None:
            low, high = self.range
            if isinstance(self.default, int) and not isinstance(self.default, bool):
                d.integer_range = [IntegerRange(from_value=int(low), to_value=int(high), step=1)]
            else:
                d.floating_point_range = [
                    FloatingPointRange(from_value=float(low), to_value=float(high))
                ]
        return d

    def help_line(self) -> str:
        """``name (default ...; range ...; read-only): description``."""
        default = (
            'no default'
            if isinstance(self.default, Parameter.Type)
            else f'default {self.default!r}'
        )
        extra = [default]
        if self.range is not None:
            extra.append(f'range [{self.range[0]:g}, {self.range[1]:g}]')
        if self.read_only:
            extra.append('read-only')
        return f'  {self.name} ({"; ".join(extra)}): {self.description}'


def param_specs(settings: Sequence[Any]) -> tuple[ParamSpec, ...]:
    """Return node parameters from ROS-free settings (name, default, description, flags, range)."""
    return tuple(
        ParamSpec(s.name, s.default, s.description, read_only=s.read_only, range=s.range)
        for s in settings
    )


def declare(node: Node, specs: Sequence[ParamSpec]) -> dict[str, Any]:
    """Declare every parameter of ``specs`` on ``node``; returns name -> value (None if unset)."""
    values = {}
    for spec in specs:
        node.declare_parameter(spec.name, spec.default, spec.descriptor())
        param = node.get_parameter_or(spec.name, Parameter(spec.name, value=None))
        values[spec.name] = param.value
    return values


def parameter_text(value: Any) -> str:
    """Return ``value`` as a ``-p name:=value`` command line writes it (YAML)."""
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, str) and value == '':
        return "''"  # YAML's empty string
    if isinstance(value, (list, tuple)):
        return '[' + ','.join(parameter_text(v) for v in value) + ']'
    return str(value)


def ros_args(params: dict[str, Any]) -> list[str]:
    """Return the ``--ros-args -p name:=value ...`` that start a node with ``params``."""
    return ['--ros-args'] + [
        a for k, v in params.items() for a in ('-p', f'{k}:={parameter_text(v)}')
    ]


def help_text(executable: str, summary: str, specs: Sequence[ParamSpec]) -> str:
    """Return what ``<executable> --help`` prints: the summary and every parameter."""
    lines = [
        f'usage: {executable} [--ros-args -p NAME:=VALUE ...]',
        '',
        summary.strip(),
        '',
        'parameters:',
    ]
    lines += [spec.help_line() for spec in specs]
    return '\n'.join(lines)


def publish_status(
    node: Node, publisher, level: bytes, message: str, hardware_id: str, **values: object
) -> None:
    """Log ``message`` at the severity of ``level`` and publish it as a DiagnosticStatus."""
    if level == DiagnosticStatus.ERROR:  # rclpy: one severity per logging call site
        node.get_logger().error(message)
    elif level == DiagnosticStatus.WARN:
        node.get_logger().warning(message)
    else:
        node.get_logger().info(message)
    publisher.publish(
        DiagnosticStatus(
            level=level,
            name=node.get_fully_qualified_name(),
            message=message,
            hardware_id=hardware_id,
            values=[KeyValue(key=k, value=str(v)) for k, v in values.items()],
        )
    )


#: Ctrl-Cs this soon after the first are the same stop (a terminal's and a launcher's).
SAME_CTRL_C_S = 2.0


#: How often a spinning node looks at its stop flag [s] (see ``_stop_handler``).
STOP_POLL_S = 0.1


def _stop_handler(stop: threading.Event) -> Callable[[int, Any], None]:
    """
    Python's SIGINT and SIGTERM handler for a node process: every stop sets ``stop``.

    rclpy's own handlers are not installed: their thread shut the context down while worker
    threads still logged (see :mod:`hexapod_util.guarded_logging`). ``run_node``'s loop sees the
    flag within ``STOP_POLL_S`` and shuts the context down itself, under the logging lock. A stop
    that comes while the node is still starting is kept by the flag too, and the node stops as
    soon as it spins (before, such a Ctrl-C was lost and the node ran on). No KeyboardInterrupt
    for the Ctrl-Cs of the first ``SAME_CTRL_C_S`` s, so a terminal's and a launcher's together
    cannot cut the node's clean-up (closing a recording) short; a Ctrl-C after that still
    interrupts a node that does not stop.
    """
    first: list[float] = []

    def on_signal(signum: int, frame: Any) -> None:
        stop.set()
        if signum != signal.SIGINT:
            return
        now = time.monotonic()
        if not first:
            first.append(now)
        elif now - first[0] > SAME_CTRL_C_S:
            raise KeyboardInterrupt

    return on_signal


#: The signal at which a node started by :func:`run_node` prints every thread's stack to stderr
#: and runs on: a launcher sends it before it escalates past Ctrl-C, so that a node that would not
#: stop says where it is stuck (``kill -USR1 PID`` does the same by hand).
STACKS_SIGNAL = signal.SIGUSR1

#: s a stopping node waits for the callbacks in flight to end before it is destroyed.
SHUTDOWN_WAIT_S = 5.0

#: s the middleware may take to tear a stopped node down (its state is saved by then). Fast DDS
#: can hang deleting a participant (eProsima/Fast-DDS#235, #2500; CI found gait_node stuck in
#: ``destroy_node`` twice, 2026-11 and 2026-12-04), holding the GIL, so no Python code can end it:
#: faulthandler's watchdog thread then prints every stack and exits with status 1, well inside a
#: launcher's 10 s between Ctrl-C and SIGTERM.
TEARDOWN_LIMIT_S = 4.0


def run_node(
    make_node: Callable[[], Node],
    args: list[str] | None = None,
    num_threads: int = 1,
    parameters: Sequence[ParamSpec] | None = None,
) -> int:
    """
    Create the node after ``rclpy.init`` and spin it (multi-threaded if ``num_threads`` > 1).

    A node whose start-up parameters are unusable raises ValueError from its constructor: that is
    printed as one line and the process exits with status 2, without a traceback. ``-h`` /
    ``--help`` (before ``--ros-args``) prints the node's parameters instead of starting.
    """
    argv = list(sys.argv[1:] if args is None else args)
    own = argv[: argv.index('--ros-args')] if '--ros-args' in argv else argv
    # SimNode -> sim_node
    executable = re.sub(r'(?<!^)(?=[A-Z])', '_', getattr(make_node, '__name__', 'node')).lower()
    if '-h' in own or '--help' in own:
        summary = (sys.modules[make_node.__module__].__doc__ or '').split('\n\n')[0]
        print(help_text(executable, summary, parameters or ()))
        return 0
    # the project's Fast DDS profile (services answer clients discovered late), unless one is set:
    # read when rclpy.init creates the DDS participant, however the node was started
    os.environ.update(profile_environment(os.environ))
    faulthandler.register(STACKS_SIGNAL, all_threads=True)
    stop = threading.Event()  # a SIGINT or SIGTERM, whenever it came
    if threading.current_thread() is threading.main_thread():
        on_signal = _stop_handler(stop)
        for signum in (signal.SIGINT, signal.SIGTERM):
            signal.signal(signum, on_signal)
    # without rclpy's signal handlers: ours stop the node, and the context goes down in one place
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    node = None
    executor = (
        MultiThreadedExecutor(num_threads=num_threads)
        if num_threads > 1
        else SingleThreadedExecutor()
    )
    try:
        try:
            node = make_node()
        except (ValueError, InvalidParameterValueException, InvalidParameterTypeException) as exc:
            print(f'[{executable}] refusing to start: {exc}', file=sys.stderr)
            return 2
        executor.add_node(node)
        while not stop.is_set() and executor.context.ok():  # executor.spin(), and the flag
            executor.spin_once(timeout_sec=STOP_POLL_S)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except RuntimeError:
        if rclpy.ok():
            raise
        # Ctrl-C shut the context down while the executor was taking a message: rclpy raises
        # RuntimeError from take_message then (ros/joint_state_publisher#117); a clean stop
    finally:
        # a signal stops the node with its context down: what still runs (a goal waiting on the
        # graph) sees it at its next check (CI, 2026-12-02: a navigate goal walked on 10 s after
        # a Ctrl-C when this waited for rclpy's signal thread)
        if stop.is_set():
            guarded_logging.shutdown()
        if node is not None:
            shutdown = getattr(node, 'shutdown', None)
            if callable(shutdown):
                shutdown()
            _let_callbacks_end(executor, SHUTDOWN_WAIT_S)
        faulthandler.dump_traceback_later(TEARDOWN_LIMIT_S, exit=True)
        if node is not None:
            node.destroy_node()
        guarded_logging.shutdown()
        faulthandler.cancel_dump_traceback_later()
        # the node is down: a Ctrl-C still on its way (a launcher's after a terminal's) must not
        # kill the process as it ends, where Python gives SIGINT back its default action
        if threading.current_thread() is threading.main_thread():
            signal.signal(signal.SIGINT, signal.SIG_IGN)
    return 0


def _let_callbacks_end(executor, timeout: float) -> None:
    """
    Wait (``timeout`` s at most) for the callbacks a multi-threaded executor still runs.

    They end before the node's entities are destroyed: a worker thread still taking an action
    goal would otherwise find the server's publishers gone (rclpy logs the task's exception,
    "Failed to take goal: feedback publisher is invalid"). rclpy's ``Executor.shutdown`` does not
    wait for them (Jazzy), so the executor's own list of tasks is read.
    """
    tasks = list(getattr(executor, '_futures', ()))
    deadline = time.monotonic() + timeout
    while any(not t.done() for t in tasks) and time.monotonic() < deadline:
        time.sleep(0.01)


def unless_closing(node: Node, call: Callable[..., Any], *args: Any) -> None:
    """
    Call ``call(*args)`` (a goal handle's ``succeed`` / ``abort``, a publish), which publishes.

    At shutdown the publishing fails (a goal handle's state is still set): that is ignored, as a
    closing node has no one to tell. While ``node``'s context is valid the error is raised.
    """
    try:
        call(*args)
    except (RCLError, InvalidHandle):
        if rclpy.ok(context=node.context):
            raise


def nodes_named(node: Node, fully_qualified_name: str) -> int:
    """How many nodes in the graph (this one included) carry ``fully_qualified_name``."""
    name = fully_qualified_name.rstrip('/')
    count = 0
    for other, namespace in node.get_node_names_and_namespaces():
        if f'{namespace.rstrip("/")}/{other}' == name:
            count += 1
    return count


def watch_for_duplicates(node: Node, report: Callable[[str], None], period: float = 2.0) -> None:
    """
    Report (once per appearance) when another node with this node's name joins the graph.

    Two simulators or two adaptation servers answering the same services make clients hang.
    """
    state = {'reported': False}

    def check() -> None:
        count = nodes_named(node, node.get_fully_qualified_name())
        if count > 1 and not state['reported']:
            report(
                f'{count} nodes named {node.get_fully_qualified_name()} are in the graph: services'
                ' and topics of that name are ambiguous; stop the extra one or start it with'
                ' another name (--ros-args -r __node:=NAME)'
            )
        state['reported'] = count > 1

    node.create_timer(period, check)


#: s without a matched server before a client says its server went away: DDS takes a moment to
#: tell a server that left from one not rediscovered yet.
SERVER_GONE_S = 2.0


class Waited(enum.Enum):
    """How a client's wait for an answer ended."""

    DONE = 'done'
    TIMEOUT = 'timeout'
    SERVER_GONE = 'server gone'


def spin_until_done(
    node: Node, future: Any, deadline: float, server_ready: Callable[[], bool]
) -> Waited:
    """
    Spin ``node`` until ``future`` is done, ``deadline`` (monotonic) passes or the server goes.

    ``server_ready`` is the client's ``service_is_ready`` or ``server_is_ready``: a server
    unmatched for :data:`SERVER_GONE_S` has gone (its node stopped), so the client can say so
    instead of waiting out its whole timeout.
    """
    gone_since = None
    while not future.done():
        if time.monotonic() >= deadline:
            return Waited.TIMEOUT
        rclpy.spin_once(node, timeout_sec=0.1)
        if future.done():
            break
        if server_ready():
            gone_since = None
        elif gone_since is None:
            gone_since = time.monotonic()
        elif time.monotonic() - gone_since > SERVER_GONE_S:
            return Waited.SERVER_GONE
    return Waited.DONE


def call_service_once(
    prog: str, srv_type: Any, name: str, request: Any, timeout: float, args: list[str], hint: str
) -> Any | None:
    """
    Call the service ``name`` once from a command-line tool; return its answer.

    None, with the reason printed as ``prog: ...`` on stderr, when the service is not there
    within ``timeout`` s (``hint`` says what to check) or does not answer in it. ``args``: the
    command's ROS arguments.
    """
    deadline = time.monotonic() + timeout
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node(prog)
    try:
        client = node.create_client(srv_type, name)
        if not client.wait_for_service(timeout_sec=timeout):
            print(f'{prog}: {client.srv_name} not available within {timeout:g} s ({hint})',
                  file=sys.stderr)  # fmt: skip
            return None
        future = client.call_async(request)
        if spin_until_done(node, future, deadline, client.service_is_ready) is not Waited.DONE:
            print(f'{prog}: no answer within {timeout:g} s', file=sys.stderr)
            return None
        return future.result()
    finally:
        node.destroy_node()
        guarded_logging.shutdown()
