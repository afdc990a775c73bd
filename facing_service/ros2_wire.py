"""Zenoh keys of ROS 2 topics, in the two formats a ROS 2 robot puts on zenoh.

- ``rmw_zenoh`` (ROS 2's zenoh middleware): ``<domain>/<topic>/<dds type>/<type hash>``,
  e.g. ``0/tf/tf2_msgs::msg::dds_::TFMessage_/RIHS01_e369d0f0...``; the topic keeps its
  inner slashes (``0/humans/faces/tracked/...``). Humble sends ``TypeHashNotSupported``
  for the hash. Payload: CDR with its encapsulation header; each sample carries an
  attachment (sequence number, source timestamp, GID) that input may ignore.
- ``bridge`` (zenoh-bridge-ros2dds, for DDS robots): the topic without its leading slash,
  under the bridge's namespace if it has one (``tf``, ``bot1/tf``); raw CDR, no attachment.

A ROS namespace (``--ros-namespace``) prefixes every topic, as a remap or the bridge's
namespace would. Pure: builds and parses strings, decides nothing else.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from enum import Enum

from . import ros2_types

HASH_NOT_SUPPORTED = "TypeHashNotSupported"


class RosFormat(str, Enum):
    RMW_ZENOH = "rmw_zenoh"
    BRIDGE = "bridge"


@dataclass(frozen=True)
class Wire:
    """Where a robot's topics are on zenoh: its format, domain and namespace."""

    format: RosFormat = RosFormat.RMW_ZENOH
    domain_id: int = 0
    namespace: str = ""  # ROS namespace or bridge namespace, without slashes around

    def _topic(self, topic: str) -> str:
        topic = topic.strip("/")
        return f"{self.namespace}/{topic}" if self.namespace else topic

    def key(self, topic: str, typename: str) -> str:
        """The key a message of ``typename`` on ``topic`` is published on."""
        if self.format is RosFormat.BRIDGE:
            return self._topic(topic)
        name = ros2_types.dds_type_name(typename)
        return f"{self.domain_id}/{self._topic(topic)}/{name}/{ros2_types.type_hash(typename)}"

    def subscription(self, topic_pattern: str, typename: str) -> str:
        """What to subscribe to for a topic (``*`` allowed in chunks), any type hash: the
        hash is checked per sample (``check``), so a mismatch is counted, not unseen."""
        if self.format is RosFormat.BRIDGE:
            return self._topic(topic_pattern)
        name = ros2_types.dds_type_name(typename)
        return f"{self.domain_id}/{self._topic(topic_pattern)}/{name}/*"

    def topic_of(self, key: str) -> str | None:
        """The ROS topic (with its leading slash, without our namespace) of a key, or None
        when the key is not one of this wire's."""
        if self.format is RosFormat.RMW_ZENOH:
            parts = key.split("/")
            if len(parts) < 4 or parts[0] != str(self.domain_id):
                return None
            key = "/".join(parts[1:-2])
        if self.namespace:
            prefix = self.namespace + "/"
            if not key.startswith(prefix):
                return None
            key = key[len(prefix) :]
        return "/" + key

    def check(self, key: str, typename: str) -> str | None:
        """Why a sample's key does not carry ``typename`` (type name or RIHS01 hash), or
        None. The bridge's keys carry no type: nothing to check."""
        if self.format is RosFormat.BRIDGE:
            return None
        parts = key.split("/")
        if len(parts) < 4 or parts[-2] != ros2_types.dds_type_name(typename):
            return f"type {parts[-2] if len(parts) >= 4 else '?'} is not {typename}"
        got = parts[-1]
        if got not in (ros2_types.type_hash(typename), HASH_NOT_SUPPORTED):
            return f"type hash {got} is not {typename}'s {ros2_types.type_hash(typename)}"
        return None


GID_SIZE = 16
ATTACHMENT_SIZE = 8 + 8 + 1 + GID_SIZE


def attachment(sequence_number: int, source_timestamp_ns: int, gid: bytes) -> bytes:
    """rmw_zenoh's per-sample attachment (its subscriptions drop samples without one):
    int64 LE sequence number (from 1 per publisher), int64 LE source timestamp in ns, the
    GID's length as one byte (16), the 16-byte publisher GID: 33 bytes."""
    if len(gid) != GID_SIZE:
        raise ValueError(f"a GID is {GID_SIZE} bytes, got {len(gid)}")
    return struct.pack("<qqB", sequence_number, source_timestamp_ns, GID_SIZE) + gid


def parse_attachment(data: bytes) -> tuple[int, int, bytes] | None:
    """``(sequence number, source timestamp ns, gid)``, or None when malformed."""
    if len(data) != ATTACHMENT_SIZE or data[16] != GID_SIZE:
        return None
    sequence_number, timestamp = struct.unpack_from("<qq", data)
    return sequence_number, timestamp, bytes(data[17:])
