"""A ROS 2 robot and ROS 2 subscriptions on zenoh, in the form of each release the service
meets, written from those releases' sources and not from facing_service (nothing here
imports it): the oracle the ROS 2 path is tested against.

Sources (read with git; the line of each rule is named where it is used):
- rmw_zenoh, ros2-gbp/rmw_zenoh-release, tags ``upstream/<version>``: Humble 0.1.x,
  Jazzy 0.2.x, Kilted 0.6.x, Rolling 0.12.x. ``liveliness_utils.cpp`` (keys, tokens, QoS
  strings), ``attachment_helpers.cpp`` (attachments), ``rmw_publisher_data.cpp``
  (caches, congestion control), ``rmw_subscription_data.cpp`` (what a subscription
  accepts).
- zenoh-bridge-ros2dds, eclipse-zenoh/zenoh-plugin-ros2dds: ``route_publisher.rs`` at tags
  1.5.0 (a ``PublicationCache`` answering on ``<key>/@ros2_pub_cache/<zid>``) and 1.5.1
  (an advanced publisher with a cache and publisher detection).

CDR is rosbags' (an independent implementation); attachments are zenoh-ext's serializer,
the one rmw_zenoh's C++ uses, and parsed back with zenoh-ros2-sdk's own parser.
"""

from __future__ import annotations

import os
import threading
import time
from dataclasses import dataclass, field
from typing import Any

import zenoh
import zenoh.ext
from zenoh.ext import Int64, z_deserialize, z_serialize

#: RIHS01 hashes as every Jazzy-or-later node computes them (ROS 2's own tf2_msgs and
#: std_msgs; ros4hri's hri_msgs 2.0.0 and hri_actions_msgs 2.0.1: tests/ros2/test_types.py).
TYPE_HASHES = {
    "tf2_msgs/msg/TFMessage": (
        "RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087"
    ),
    "std_msgs/msg/String": (
        "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"
    ),
    "hri_msgs/msg/IdsList": (
        "RIHS01_7e0812d1ac945c98fd3e393568d581ad0ab567f37b24eff633eab778c1bfe62d"
    ),
    "hri_msgs/msg/EngagementLevel": (
        "RIHS01_275391f46d2e6cc0d21085f8e02dce6a8150baa57539ec99bd9f4e0321443788"
    ),
    "visualization_msgs/msg/MarkerArray": (
        "RIHS01_86cb8800b6fb05b5eff1abd7a56f62a5641d3ae9a1c29e78e67e704f1d067dcf"
    ),
    "hri_msgs/msg/Group": (
        "RIHS01_8a5322be10347f118545806061283201525b8f572bfe6131b4b45b70c56f2935"
    ),
    "hri_msgs/msg/Gaze": (
        "RIHS01_e8c46fafadbeca4367ca1987944b54863fcfc0175319002a76df5298570f4ab3"
    ),
    "hri_actions_msgs/msg/Intent": (
        "RIHS01_850d5c0a06aecf153f4cbc75f27fc655d687f93300bcc928a9d21712716fcfaa"
    ),
}


@dataclass(frozen=True)
class Release:
    """What one release puts on the wire."""

    name: str
    bridge: bool = False
    type_hash: bool = True  # Humble: "TypeHashNotSupported" (rmw_publisher_data.cpp)
    keyed_attachment: bool = False  # before Humble 0.1.2 / Jazzy 0.2.4
    publication_cache: bool = False  # rmw_zenoh before Humble 0.1.2 / Jazzy 0.2.2; bridge <= 1.5.0

    def __str__(self) -> str:
        return self.name


HUMBLE_0_1_1 = Release("rmw_zenoh Humble 0.1.1", type_hash=False, keyed_attachment=True,
                       publication_cache=True)  # fmt: skip
HUMBLE_0_1_9 = Release("rmw_zenoh Humble 0.1.9", type_hash=False)
JAZZY_0_2_3 = Release("rmw_zenoh Jazzy 0.2.3", keyed_attachment=True)
JAZZY_0_2_10 = Release("rmw_zenoh Jazzy 0.2.10")
KILTED_0_6_7 = Release("rmw_zenoh Kilted 0.6.7")
ROLLING_0_12_0 = Release("rmw_zenoh Rolling 0.12.0")
BRIDGE_1_5_0 = Release("zenoh-bridge-ros2dds 1.5.0", bridge=True, publication_cache=True)
BRIDGE_1_10_0 = Release("zenoh-bridge-ros2dds 1.10.0", bridge=True)


def dds_type(typename: str) -> str:
    package, kind, name = typename.split("/")
    return f"{package}::{kind}::dds_::{name}_"


def topic_key(release: Release, topic: str, typename: str, domain: int = 0, ns: str = "") -> str:
    """TopicInfo's ``topic_keyexpr_`` (``<domain>/<topic>/<type>/<hash>``), or the
    bridge's key (the topic under its namespace)."""
    name = (f"/{ns}" if ns else "") + topic
    if release.bridge:
        return name.strip("/")
    hash_ = TYPE_HASHES[typename] if release.type_hash else "TypeHashNotSupported"
    return f"{domain}/{name.strip('/')}/{dds_type(typename)}/{hash_}"


def make_attachment(release: Release, sequence_number: int, gid: bytes) -> bytes:
    """``AttachmentData::serialize_to_zbytes``: the fields, each after its name before
    0.1.2 / 0.2.4."""
    fields: tuple[Any, ...] = (Int64(sequence_number), Int64(time.time_ns()), gid)
    if release.keyed_attachment:
        names = ("sequence_number", "source_timestamp", "source_gid")
        fields = tuple(x for pair in zip(names, fields, strict=True) for x in pair)
    return z_serialize(fields).to_bytes()


def parse_attachment(release: Release, data: bytes) -> tuple[int, bytes]:
    """``AttachmentData(const zenoh::Bytes &)``: (sequence number, gid); raises where that
    constructor throws (and the subscription drops the sample)."""
    if release.keyed_attachment:
        fields = z_deserialize(tuple[str, Int64, str, Int64, str, bytes], zenoh.ZBytes(data))
        if fields[0::2] != ("sequence_number", "source_timestamp", "source_gid"):
            raise ValueError(f"not a keyed attachment: {fields[0::2]}")
        return int(fields[1]), bytes(fields[5])
    from zenoh_ros2_sdk.attachment import Attachment

    parsed = Attachment.from_bytes(data)
    if len(data) != 33 or len(parsed.gid) != 16:
        raise ValueError(f"a current attachment is 33 bytes with a 16-byte GID, got {len(data)}")
    return parsed.sequence_id, parsed.gid


class Robot:
    """Publishes a robot's topics as ``release`` does. Close it to undeclare everything."""

    def __init__(
        self, session: zenoh.Session, release: Release, domain: int = 0, namespace: str = ""
    ) -> None:
        self.session = session
        self.release = release
        self.domain = domain
        self.namespace = namespace
        self._writers: dict[str, _Writer] = {}
        self._entities: list[Any] = []
        if not release.bridge:  # the node's token, as `ros2 node list` reads it
            self._token("NN", 0, "")

    def key(self, topic: str, typename: str) -> str:
        return topic_key(self.release, topic, typename, self.domain, self.namespace)

    def _token(self, kind: str, entity: int, tail: str) -> None:
        ns = ("%" + self.namespace) if self.namespace else "%"
        key = f"@ros2_lv/{self.domain}/{self.session.zid()}/0/{entity}/{kind}/%/{ns}/robot{tail}"
        self._entities.append(self.session.liveliness().declare_token(key))

    def publish(self, topic: str, typename: str, cdr: bytes, *, latched: bool = False) -> None:
        """One message; ``latched``: on a transient-local topic (depth 1)."""
        writer = self._writers.get(topic)
        if writer is None:
            writer = self._writers[topic] = self._declare(topic, typename, latched)
        writer.put(cdr)

    def _declare(self, topic: str, typename: str, latched: bool) -> _Writer:
        key = self.key(topic, typename)
        release = self.release
        if not release.bridge:
            qos = "::,1:,:,:,," if not latched else ":1:,1:,:,:,,"  # qos_to_keyexpr
            name = ("/" + self.namespace if self.namespace else "") + topic
            tail = f"/{name.replace('/', '%')}/{dds_type(typename)}/{key.rsplit('/', 1)[1]}/{qos}"
            self._token("MP", len(self._writers) + 1, tail)
        writer = _Writer(release, os.urandom(16))
        if latched and release.publication_cache:
            writer.entity = self.session.declare_publisher(key)
            # rmw_zenoh 0.1.0: queryable_prefix = the zenoh id; the bridge 1.5.0:
            # queryable_suffix = @ros2_pub_cache/<zid>. Replies carry the sample's key.
            prefix = str(self.session.zid())
            where = f"{key}/@ros2_pub_cache/{prefix}" if release.bridge else f"{prefix}/{key}"
            self._entities.append(self.session.declare_queryable(where, writer.answer))
            writer.key = key
        elif latched:  # an advanced publisher's cache (rmw_zenoh >= 0.1.2, bridge >= 1.5.1)
            writer.entity = zenoh.ext.declare_advanced_publisher(
                self.session,
                key,
                cache=zenoh.ext.CacheConfig(1),
                publisher_detection=True,
                sample_miss_detection=None if release.bridge else zenoh.ext.MissDetectionConfig(),
            )
        else:  # reliable keep-last: DROP (rmw_publisher_data.cpp)
            writer.entity = self.session.declare_publisher(
                key, congestion_control=zenoh.CongestionControl.DROP
            )
        return writer

    def close(self) -> None:
        for writer in self._writers.values():
            writer.entity.undeclare()
        self._writers.clear()
        for entity in self._entities:
            entity.undeclare()
        self._entities.clear()


@dataclass
class _Writer:
    release: Release
    gid: bytes
    entity: Any = None
    key: str = ""
    sequence_number: int = 0
    last: tuple[bytes, bytes | None] | None = None  # what a publication cache holds

    def put(self, cdr: bytes) -> None:
        self.sequence_number += 1  # rmw_zenoh numbers from 1
        extra = None
        if not self.release.bridge:
            extra = make_attachment(self.release, self.sequence_number, self.gid)
        self.last = (cdr, extra)
        self.entity.put(cdr, attachment=extra)

    def answer(self, query: zenoh.Query) -> None:
        if self.last is not None:
            query.reply(self.key, self.last[0], attachment=self.last[1])
        query.drop()


@dataclass
class Received:
    payload: bytes
    sequence_number: int | None
    at: float = field(default_factory=time.monotonic)  # when it arrived


@dataclass
class Subscription:
    """rmw_zenoh's subscription (``rmw_subscription_data.cpp``): the exact key of its form,
    hash included; a sample without an attachment, or one its release cannot parse, is
    dropped. The bridge's: the topic's key, raw CDR."""

    release: Release
    key: str
    received: list[Received] = field(default_factory=list)
    dropped: int = 0
    _lock: threading.Lock = field(default_factory=threading.Lock)
    _entity: Any = None

    @classmethod
    def open(cls, session: zenoh.Session, release: Release, topic: str, typename: str,
             domain: int = 0, ns: str = "") -> Subscription:  # fmt: skip
        sub = cls(release, topic_key(release, topic, typename, domain, ns))
        sub._entity = session.declare_subscriber(sub.key, sub._on_sample)
        return sub

    def _on_sample(self, sample: zenoh.Sample) -> None:
        number = None
        if not self.release.bridge:
            try:
                assert sample.attachment is not None, "no attachment"
                number, _ = parse_attachment(self.release, sample.attachment.to_bytes())
            except Exception:  # AttachmentData's constructor throws: the sample is lost
                with self._lock:
                    self.dropped += 1
                return
        with self._lock:
            self.received.append(Received(sample.payload.to_bytes(), number))

    def messages(self) -> list[Received]:
        with self._lock:
            return list(self.received)

    def close(self) -> None:
        self._entity.undeclare()
