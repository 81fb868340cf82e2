# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
MCAP recording of an adaptation run.

ROS 2 CDR messages with ``ros2msg`` schemas, readable by Foxglove, by ``ros2 bag`` on a full ROS
install, by the ``mcap`` readers and by :func:`read_messages` here.

Messages are serialised by rclpy's own type support (the same bytes a ROS 2 recorder stores).
The file is chunked (zstd), and a cleanly closed file (end of the run, Ctrl-C, SIGTERM) has the
chunk and message indexes, statistics and summary that ``ros2 bag`` writes, so indexed readers
(``mcap`` ``make_reader``, Foxglove) read every message. :meth:`McapRecorder.checkpoint` ends
the chunk in progress, flushes it and fsyncs the file: the adapt node calls it after every
trial, so a run killed hard -- or a power loss -- keeps every trial completed before it. Such a
file has no index; ``recover_recording`` (:func:`recover`) rewrites it as a valid indexed MCAP.
Files are created exclusively under unique names (:func:`create_recording`): a recording is
never overwritten.
"""

from __future__ import annotations

from dataclasses import dataclass
import importlib
import os
from pathlib import Path
import re
import struct
import threading
import time
from typing import Any, Iterator, Mapping

from ament_index_python.packages import get_package_share_directory, PackageNotFoundError
from hexapod_util.files import atomic_output
from mcap.exceptions import McapError
from mcap.reader import make_reader
from mcap.records import Channel, Message, Schema
from mcap.stream_reader import StreamReader
from mcap.writer import CompressionType, Writer
from rclpy.serialization import deserialize_message, serialize_message
import zstandard

_BUILTIN = {
    'bool',
    'byte',
    'char',
    'float32',
    'float64',
    'int8',
    'uint8',
    'int16',
    'uint16',
    'int32',
    'uint32',
    'int64',
    'uint64',
    'string',
    'wstring',
}
_SEPARATOR = '=' * 80


class SchemaUnavailable(LookupError):
    """The definition of a message type (or of a type nested in it) cannot be found."""

    def __init__(self, type_name: str, why: str):
        super().__init__(f'no definition of {type_name}: {why}')
        self.type_name = type_name
        self.why = why


def _msg_text(full_type: str) -> str:
    """Return the text of ``pkg/msg/Type.msg`` from its package's share directory."""
    pkg, _, name = full_type.split('/')
    try:
        return (Path(get_package_share_directory(pkg)) / 'msg' / f'{name}.msg').read_text()
    except PackageNotFoundError:
        raise SchemaUnavailable(
            full_type, f"package '{pkg}' is not in the ament index (AMENT_PREFIX_PATH)"
        ) from None
    except OSError as exc:
        raise SchemaUnavailable(full_type, f'{exc.strerror}: {exc.filename}') from None


def _dependencies(full_type: str, text: str) -> list[str]:
    pkg = full_type.split('/')[0]
    deps = []
    for line in text.splitlines():
        line = line.split('#', 1)[0].strip()
        if not line or '=' in line.split()[0]:
            continue
        base = re.sub(r'\[.*\]$', '', line.split()[0])
        base = re.sub(r'<=\d+$', '', base)
        if base in _BUILTIN or base.startswith(('string<', 'wstring<')):
            continue
        if '/' in base:
            dep_pkg, dep_name = base.split('/')
        else:
            dep_pkg, dep_name = pkg, base
        deps.append(f'{dep_pkg}/msg/{dep_name}')
    return deps


def schema_text(full_type: str) -> str:
    """
    Return the ros2msg schema of ``pkg/msg/Type``.

    Its definition, then every nested type's after a separator line (the layout rosbag2 writes).
    :class:`SchemaUnavailable` names the type whose definition is missing.
    """
    main = _msg_text(full_type)
    seen: set[str] = {full_type}
    parts: list[str] = [main.rstrip('\n')]
    queue = _dependencies(full_type, main)
    while queue:
        dep = queue.pop(0)
        if dep in seen:
            continue
        seen.add(dep)
        text = _msg_text(dep)
        pkg, _, name = dep.split('/')
        parts.append(f'{_SEPARATOR}\nMSG: {pkg}/{name}\n{text.rstrip(chr(10))}')
        queue.extend(_dependencies(dep, text))
    return '\n'.join(parts) + '\n'


def type_name(msg_or_class: Any) -> str:
    """Return ``pkg/msg/Type`` of a message or message class."""
    cls = msg_or_class if isinstance(msg_or_class, type) else type(msg_or_class)
    return f'{cls.__module__.split(".")[0]}/msg/{cls.__name__}'


def offered_qos_yaml(qos: Any) -> str:
    """
    Return the ros2 MCAP profile's ``offered_qos_profiles`` of one publisher with ``qos``.

    ``qos`` is an rclpy QoSProfile. Enums as rmw numbers (history 1 keep last, 2 keep all;
    reliability 1 reliable, 2 best effort; durability 1 transient local, 2 volatile; liveliness
    1 automatic), durations as sec/nsec: what ``ros2 bag play`` reads to offer the topic again
    as it was offered, so that latched topics replay latched.
    """

    def duration(d: Any) -> str:
        ns = d.nanoseconds
        if ns == 0:  # unset: rmw's 'infinite' as rosbag2 writes it
            return '\n    sec: 9223372036\n    nsec: 854775807'
        return f'\n    sec: {ns // 1_000_000_000}\n    nsec: {ns % 1_000_000_000}'

    return (
        f'- history: {int(qos.history)}\n'
        f'  depth: {int(qos.depth)}\n'
        f'  reliability: {int(qos.reliability)}\n'
        f'  durability: {int(qos.durability)}\n'
        f'  deadline:{duration(qos.deadline)}\n'
        f'  lifespan:{duration(qos.lifespan)}\n'
        f'  liveliness: {int(qos.liveliness) or 1}\n'
        f'  liveliness_lease_duration:{duration(qos.liveliness_lease_duration)}\n'
        f'  avoid_ros_namespace_conventions: false\n'
    )


class RecordingClosed(RuntimeError):
    """A message came for a recording that has already been finished."""


class McapRecorder:
    """
    Write ROS 2 messages to one new MCAP file (``record(topic, msg)``).

    ``checkpoint()`` makes everything so far durable; ``close()`` finishes the file with its index
    and summary.
    """

    def __init__(self, path: str | os.PathLike, qos: Mapping[str, Any] | None = None):
        self.path = Path(path)
        # topic -> the QoS it is offered with (rclpy QoSProfile): the channel's metadata
        self._qos = dict(qos or {})
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._file = open(self.path, 'xb')  # exclusive: never overwrite a recording
        self._writer = Writer(self._file, chunk_size=1 << 20, compression=CompressionType.ZSTD)
        self._writer.start(profile='ros2', library='hexapod_adapt')
        self._schemas: dict[str, int] = {}
        self._channels: dict[str, int] = {}
        self._closed = False
        self._lock = threading.Lock()  # a node records from several threads and closes on shutdown

    def record(self, topic: str, msg: Any, log_time_ns: int | None = None) -> None:
        """Add one message on ``topic`` (the time defaults to the wall clock)."""
        data = serialize_message(msg)
        with self._lock:
            self._record(topic, msg, data, log_time_ns)

    def _record(self, topic: str, msg: Any, data: bytes, log_time_ns: int | None) -> None:
        if self._closed:
            raise RecordingClosed(f'{self.path} is closed')
        name = type_name(msg)
        if name not in self._schemas:
            self._register(name)
        if topic not in self._channels:
            qos = self._qos.get(topic)
            self._channels[topic] = self._writer.register_channel(
                topic,
                'cdr',
                self._schemas[name],
                {'offered_qos_profiles': offered_qos_yaml(qos)} if qos is not None else {},
            )
        now = log_time_ns if log_time_ns is not None else time.time_ns()
        self._writer.add_message(self._channels[topic], log_time=now, data=data, publish_time=now)

    def register_type(self, name: str) -> None:
        """
        Resolve and store the schema of ``pkg/msg/Type`` now, before any message of it comes.

        :class:`SchemaUnavailable` names the type whose definition is missing.
        """
        with self._lock:
            if self._closed:
                raise RecordingClosed(f'{self.path} is closed')
            if name not in self._schemas:
                self._register(name)

    def _register(self, name: str) -> None:
        text = schema_text(name)  # may raise SchemaUnavailable: nothing is written then
        self._schemas[name] = self._writer.register_schema(name, 'ros2msg', text.encode())

    def checkpoint(self) -> None:
        """End the chunk in progress and fsync: what was recorded survives a kill or power loss."""
        with self._lock:
            if self._closed:
                return
            self._writer.flush()
            os.fsync(self._file.fileno())

    def close(self) -> None:
        """Finish the file (indexes, statistics, summary, footer) and fsync it."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            self._writer.finish()
            self._file.flush()
            os.fsync(self._file.fileno())
            self._file.close()

    def __enter__(self) -> 'McapRecorder':
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def create_recording(
    directory: str | os.PathLike, prefix: str = 'adapt', qos: Mapping[str, Any] | None = None
) -> McapRecorder:
    """
    Return a recorder on a new file ``<prefix>_<UTC date-time>[_<n>].mcap`` in ``directory``.

    The first name not taken, created exclusively (several runs in one second each get their own).
    ``qos``: topic -> the QoSProfile it is offered with (each channel's ``offered_qos_profiles``).
    """
    directory = Path(directory)
    stamp = time.strftime('%Y%m%d_%H%M%S', time.gmtime())
    for n in range(1, 10_000):
        path = directory / (f'{prefix}_{stamp}.mcap' if n == 1 else f'{prefix}_{stamp}_{n}.mcap')
        try:
            return McapRecorder(path, qos)
        except FileExistsError:
            continue
    raise OSError(f'no free recording name for {prefix}_{stamp} in {directory}')


def message_class(full_type: str) -> type:
    """Return the Python class of ``pkg/msg/Type``."""
    pkg, kind, name = full_type.split('/')
    return getattr(importlib.import_module(f'{pkg}.{kind}'), name)


def _complete_records(path: str | os.PathLike) -> Iterator[Any]:
    """
    Every complete record of an MCAP file, chunks opened, stopping at a truncated tail.

    Chunks are checked against their CRCs: a damaged one ends the records there, so that nothing
    corrupted is passed on as a message.
    """
    with open(path, 'rb') as fh:
        records = StreamReader(fh, skip_magic=False, validate_crcs=True).records
        while True:
            try:
                yield next(records)
            except StopIteration:
                return
            except (
                McapError,
                EOFError,
                ValueError,
                IndexError,
                OSError,
                struct.error,
                zstandard.ZstdError,
            ):
                return  # a truncated tail after a hard kill


def read_messages(path: str | os.PathLike) -> Iterator[tuple[str, Any, int]]:
    """
    Yield (topic, decoded message, log time ns) for every complete message in the file.

    This includes a file whose writer was killed before it could finish (its incomplete tail
    is skipped).
    """
    schemas: dict[int, Any] = {}
    channels: dict[int, tuple[str, Any]] = {}
    for record in _complete_records(path):
        if isinstance(record, Schema):
            schemas[record.id] = message_class(record.name)
        elif isinstance(record, Channel):
            channels[record.id] = (record.topic, schemas[record.schema_id])
        elif isinstance(record, Message):
            topic, cls = channels[record.channel_id]
            yield topic, deserialize_message(record.data, cls), record.log_time


#: The 8 bytes every MCAP file starts with (the MCAP specification's magic).
MCAP_MAGIC = b'\x89MCAP0\r\n'


class NotARecording(ValueError):
    """A file recover() cannot rewrite: not an MCAP file, or no readable record in it."""


def recording_problem(path: str | os.PathLike) -> str:
    """Say why ``path`` is not an MCAP recording recover() can read ('' if it is one)."""
    with open(path, 'rb') as fh:
        head = fh.read(len(MCAP_MAGIC))
    if head != MCAP_MAGIC:
        return f'{path} is not an MCAP file (it does not start with the MCAP magic bytes)'
    if next(_complete_records(path), None) is None:
        return f'{path} holds no readable MCAP record'
    return ''


def readable_messages(path: str | os.PathLike) -> int:
    """
    Count the messages a reader can get out of ``path``: the most of two ways of reading it.

    Its complete records in order (what :func:`recover` keeps), and, for a file that was
    finished, its index (what Foxglove and ``mcap``'s indexed reader read).
    """
    streamed = sum(isinstance(r, Message) for r in _complete_records(path))
    indexed = 0
    try:
        with open(path, 'rb') as fh:
            summary = make_reader(fh).get_summary()
            if summary is not None and summary.statistics is not None:
                indexed = summary.statistics.message_count
    except (McapError, EOFError, ValueError, IndexError, OSError, struct.error):
        pass  # no usable index (a file whose writer was killed)
    return max(streamed, indexed)


@dataclass(frozen=True)
class Recovery:
    """What :func:`recover` kept."""

    messages: int
    channels: int
    out: Path


def recover(src: str | os.PathLike, dst: str | os.PathLike | None = None) -> Recovery:
    """
    Rewrite a recording whose writer was killed as a valid, indexed MCAP.

    Every complete message of ``src`` is kept; the result is written atomically to ``dst``
    (default: ``src`` itself). :class:`NotARecording` says why a file cannot be read, before
    anything is written.
    """
    src = Path(src)
    dst = Path(dst) if dst is not None else src
    problem = recording_problem(src)
    if problem:
        raise NotARecording(problem)
    schema_map: dict[int, int] = {}
    channel_map: dict[int, int] = {}
    count = 0
    with atomic_output(dst) as out:
        writer = Writer(out, chunk_size=1 << 20, compression=CompressionType.ZSTD)
        writer.start(profile='ros2', library='hexapod_adapt recover')
        for record in _complete_records(src):
            if isinstance(record, Schema) and record.id not in schema_map:
                schema_map[record.id] = writer.register_schema(
                    record.name, record.encoding, record.data
                )
            elif isinstance(record, Channel) and record.id not in channel_map:
                channel_map[record.id] = writer.register_channel(
                    record.topic,
                    record.message_encoding,
                    schema_map.get(record.schema_id, 0),
                    dict(record.metadata),
                )
            elif isinstance(record, Message) and record.channel_id in channel_map:
                writer.add_message(
                    channel_map[record.channel_id],
                    log_time=record.log_time,
                    data=record.data,
                    publish_time=record.publish_time,
                    sequence=record.sequence,
                )
                count += 1
        writer.finish()
    return Recovery(count, len(channel_map), dst)
