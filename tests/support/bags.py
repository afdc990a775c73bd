"""The team's ROS 2 recordings read straight with rosbags, as the tests need them (the
service replays a bag through ``tools.replay``, which sends each message as it is)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

from rosbags.highlevel import AnyReader

from facing_service.ros2 import types as ros2_types


def messages(path: Path, decode: bool = True) -> Iterator[tuple[str, str, int, Any]]:
    """``(topic, type name, receive time in ns, message)`` of a bag (sqlite3 or mcap), in
    order; the message decoded, or its CDR bytes (``decode=False``: what a replay sends)."""
    with AnyReader([Path(path)], default_typestore=ros2_types.typestore()) as reader:
        for connection, timestamp, raw in reader.messages():
            message = reader.deserialize(raw, connection.msgtype) if decode else bytes(raw)
            yield connection.topic, connection.msgtype, timestamp, message
