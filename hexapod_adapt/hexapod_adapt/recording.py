"""MCAP recording of an adaptation run: ROS 2 CDR messages with ``ros2msg`` schemas, readable by
Foxglove, by ``ros2 bag`` on a full ROS install and by :func:`read_messages` here.

Messages are serialised by rclpy's own type support (the same bytes a ROS 2 recorder stores).
The file is written without chunks and flushed after every message, so a run killed hard
(SIGKILL, power loss) leaves a file whose every complete message still reads back; a run
stopped cleanly (Ctrl-C, SIGTERM, the end of the run) also gets MCAP's index and footer.
"""
from __future__ import annotations

import os
import re
import struct
import threading
import time
from pathlib import Path
from typing import Any, Iterator

_BUILTIN = {"bool", "byte", "char", "float32", "float64", "int8", "uint8", "int16", "uint16", "int32",
            "uint32", "int64", "uint64", "string", "wstring"}
_SEPARATOR = "=" * 80


def _msg_file(full_type: str) -> Path:
    from ament_index_python.packages import get_package_share_directory

    pkg, _, name = full_type.split("/")
    return Path(get_package_share_directory(pkg)) / "msg" / f"{name}.msg"


def _dependencies(full_type: str, text: str) -> list[str]:
    pkg = full_type.split("/")[0]
    deps = []
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        if not line or "=" in line.split()[0]:
            continue
        base = re.sub(r"\[.*\]$", "", line.split()[0])
        base = re.sub(r"<=\d+$", "", base)
        if base in _BUILTIN or base.startswith(("string<", "wstring<")):
            continue
        if "/" in base:
            dep_pkg, dep_name = base.split("/")
        else:
            dep_pkg, dep_name = pkg, base
        deps.append(f"{dep_pkg}/msg/{dep_name}")
    return deps


def schema_text(full_type: str) -> str:
    """The ros2msg schema of ``pkg/msg/Type``: its definition, then every nested type's after a
    separator line (the layout rosbag2 writes)."""
    main = _msg_file(full_type).read_text()
    seen: set[str] = {full_type}
    parts: list[str] = [main.rstrip("\n")]
    queue = _dependencies(full_type, main)
    while queue:
        dep = queue.pop(0)
        if dep in seen:
            continue
        seen.add(dep)
        text = _msg_file(dep).read_text()
        pkg, _, name = dep.split("/")
        parts.append(f"{_SEPARATOR}\nMSG: {pkg}/{name}\n{text.rstrip(chr(10))}")
        queue.extend(_dependencies(dep, text))
    return "\n".join(parts) + "\n"


def _type_name(msg: Any) -> str:
    module = type(msg).__module__.split(".")[0]
    return f"{module}/msg/{type(msg).__name__}"


class McapRecorder:
    """Write ROS 2 messages to one MCAP file (``record(topic, msg)``); ``close()`` finishes it."""

    def __init__(self, path: str | os.PathLike):
        from mcap.writer import Writer

        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._file = open(self.path, "wb")
        self._writer = Writer(self._file, use_chunking=False)
        self._writer.start(profile="ros2", library="hexapod_adapt")
        self._schemas: dict[str, int] = {}
        self._channels: dict[str, int] = {}
        self._closed = False
        self._lock = threading.Lock()     # a node records from several threads and closes on shutdown
        self._file.flush()

    def record(self, topic: str, msg: Any, log_time_ns: int | None = None) -> None:
        from rclpy.serialization import serialize_message

        data = serialize_message(msg)
        with self._lock:
            self._record(topic, msg, data, log_time_ns)

    def _record(self, topic: str, msg: Any, data: bytes, log_time_ns: int | None) -> None:
        if self._closed:
            raise RuntimeError(f"{self.path} is closed")
        type_name = _type_name(msg)
        if type_name not in self._schemas:
            self._schemas[type_name] = self._writer.register_schema(type_name, "ros2msg",
                                                                    schema_text(type_name).encode())
        if topic not in self._channels:
            self._channels[topic] = self._writer.register_channel(topic, "cdr", self._schemas[type_name])
        now = log_time_ns if log_time_ns is not None else time.time_ns()
        self._writer.add_message(self._channels[topic], log_time=now, data=data, publish_time=now)
        self._file.flush()

    def close(self) -> None:
        with self._lock:
            if self._closed:
                return
            self._closed = True
            self._writer.finish()
            self._file.flush()
            os.fsync(self._file.fileno())
            self._file.close()

    def __enter__(self) -> "McapRecorder":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def message_class(full_type: str) -> type:
    """The Python class of ``pkg/msg/Type``."""
    import importlib

    pkg, kind, name = full_type.split("/")
    return getattr(importlib.import_module(f"{pkg}.{kind}"), name)


def read_messages(path: str | os.PathLike) -> Iterator[tuple[str, Any, int]]:
    """(topic, decoded message, log time ns) for every complete message in the file, including
    a file whose writer was killed before it could finish (its incomplete tail is skipped)."""
    from mcap.exceptions import McapError
    from mcap.records import Channel, Message, Schema
    from mcap.stream_reader import StreamReader
    from rclpy.serialization import deserialize_message

    schemas: dict[int, Any] = {}
    channels: dict[int, tuple[str, Any]] = {}
    with open(path, "rb") as fh:
        reader = StreamReader(fh, skip_magic=False)
        records = reader.records
        while True:
            try:
                record = next(records)
            except StopIteration:
                return
            except (McapError, EOFError, ValueError, IndexError, OSError, struct.error):
                return   # a truncated tail after a hard kill
            if isinstance(record, Schema):
                schemas[record.id] = message_class(record.name)
            elif isinstance(record, Channel):
                channels[record.id] = (record.topic, schemas[record.schema_id])
            elif isinstance(record, Message):
                topic, cls = channels[record.channel_id]
                yield topic, deserialize_message(record.data, cls), record.log_time
