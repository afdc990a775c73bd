"""ROS 2 message types on the wire: names, RIHS01 hashes, CDR, bags, through ``rosbags``.

rosbags is a well-kept, independent pure-Python implementation of ROS 2's CDR, bag formats
and type hashes; hand-written parsers would be ours to get wrong. Types rosbags does not
ship (``hri_msgs``) are registered from their upstream ``.msg`` files kept in ``msg/``.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..contract.stamps import Time

if TYPE_CHECKING:
    from rosbags.typesys.store import Typestore

# rosbags is imported where it is used: a service on JSON input never loads it (measured:
# 7 MB of RSS and ~70 ms of start-up saved).

MSG_DIR = Path(__file__).resolve().parent / "msg"

TF_MESSAGE = "tf2_msgs/msg/TFMessage"
IDS_LIST = "hri_msgs/msg/IdsList"
STRING = "std_msgs/msg/String"


@cache
def typestore() -> Typestore:
    """ROS 2 Jazzy's standard types plus the upstream definitions in ``msg/``."""
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    store = get_typestore(Stores.ROS2_JAZZY)
    for path in sorted(MSG_DIR.glob("*/*.msg")):
        name = f"{path.parent.name}/msg/{path.stem}"
        store.register(get_types_from_msg(path.read_text(), name))
    return store


def dds_type_name(typename: str) -> str:
    """``tf2_msgs/msg/TFMessage`` -> ``tf2_msgs::msg::dds_::TFMessage_`` (rmw_zenoh's keys)."""
    package, kind, name = typename.split("/")
    return f"{package}::{kind}::dds_::{name}_"


@cache
def type_hash(typename: str) -> str:
    """The RIHS01 hash of a type, as rmw_zenoh puts it in keys: ``RIHS01_<sha256 hex>``."""
    return typestore().hash_rihs01(typename)


def deserialize(data: bytes, typename: str) -> Any:
    """CDR bytes (with their 4-byte encapsulation header) -> message; raises on bad data."""
    return typestore().deserialize_cdr(data, typename)


def serialize(message: Any, typename: str) -> bytes:
    """Message -> CDR bytes, little-endian, with the encapsulation header."""
    return bytes(typestore().serialize_cdr(message, typename))


def message_type(typename: str) -> Any:
    """The message class, to build messages: ``message_type(STRING)(data="x")``."""
    return typestore().types[typename]


def header(frame_id: str, stamp: Time) -> Any:
    """A ``std_msgs/Header``: every message we send carries one."""
    time = message_type("builtin_interfaces/msg/Time")(sec=stamp.sec, nanosec=stamp.nanosec)
    return message_type("std_msgs/msg/Header")(stamp=time, frame_id=frame_id)
