"""ROS 2 bags read as the benchmarks need them (the service itself replays a bag
through ``tools.replay``, which sends each message as it is)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

from rosbags.highlevel import AnyReader

from facing_service.ros2 import types as ros2_types


def read_bag(path: Path) -> Iterator[tuple[str, int, Any]]:
    """``(topic, receive time in ns, message)`` of a ROS 2 bag (sqlite3 or mcap), in order."""
    with AnyReader([Path(path)], default_typestore=ros2_types.typestore()) as reader:
        for connection, timestamp, raw in reader.messages():
            yield connection.topic, timestamp, reader.deserialize(raw, connection.msgtype)


def read_bag_raw(path: Path) -> Iterator[tuple[str, str, int, bytes]]:
    """``(topic, type name, receive time in ns, CDR bytes)``: what a replay sends as it is."""
    with AnyReader([Path(path)], default_typestore=ros2_types.typestore()) as reader:
        for connection, timestamp, raw in reader.messages():
            yield connection.topic, connection.msgtype, timestamp, bytes(raw)
