"""The robot's topics on zenoh: what the shell declares for the ROS 2 adapter (``ros2/``
is pure and never sees a session).

- ``received``: a zenoh sample as the plain ``RosSample`` the adapter routes;
- ``RobotSubscriptions``: the robot's topics (transient-local ones through zenoh-ext
  advanced subscribers, and the older generation's publication caches queried; see
  ``ros2.input`` for which robots need which);
- ``RobotPublishers`` and ``TopicWriter``: our answers on the robot's topics, in its format
  and each form it is answered in, with rmw_zenoh's liveliness tokens and attachments;
- ``robot_topic_writer``: a robot's own topics, as a replayed or simulated robot
  publishes them.
"""

from __future__ import annotations

import hashlib
import os
import threading
import time
from collections.abc import Callable, Iterable
from dataclasses import replace
from typing import Any

import zenoh
import zenoh.ext

from ..contract.robot import DEFAULT_MAX_MESSAGE_BYTES
from ..ros2 import types as ros2_types
from ..ros2.input import TOPICS, RosSample, publication_cache_selector
from ..ros2.wire import (
    GID_SIZE,
    QOS_RELIABLE_VOLATILE,
    Form,
    FormLearner,
    RosFormat,
    Wire,
    attachment,
)
from .outbox import Kind, Publication

CDR = zenoh.Encoding("application/cdr")
#: The second query of the older generation's publication caches, after the first at start.
CACHE_QUERY_AGAIN_S = 2.0


def received(sample: zenoh.Sample, max_bytes: int = DEFAULT_MAX_MESSAGE_BYTES) -> RosSample:
    """The sample as plain bytes; a payload over ``max_bytes`` is not even copied."""
    extra = None if sample.attachment is None else sample.attachment.to_bytes()
    if (size := len(sample.payload)) > max_bytes:
        return RosSample(str(sample.key_expr), b"", extra, size)
    return RosSample(str(sample.key_expr), sample.payload.to_bytes(), extra)


def query_publication_caches(
    session: zenoh.Session,
    selectors: Iterable[str],
    on_sample: Callable[[zenoh.Sample], None],
) -> None:
    """Query publication caches as their generation's late joiners did: every replier
    (target ALL), every reply (no consolidation: /tf_static has many publishers), on any
    key (they answer on the sample's own). Quietly nothing once the session is closed."""

    def on_reply(reply: zenoh.Reply) -> None:
        if (sample := reply.ok) is not None:
            on_sample(sample)

    for selector in selectors:
        try:
            session.get(
                selector,
                on_reply,
                target=zenoh.QueryTarget.ALL,
                consolidation=zenoh.ConsolidationMode.NONE,
                accept_replies=zenoh.ReplyKeyExpr.ANY,
            )
        except zenoh.ZError:
            return


class RobotSubscriptions:
    """The robot's topics on a zenoh session, but ``skip`` (a topic the caller reads
    itself); each sample goes to ``hand_off`` as a RosSample (the service's intake).
    Close it to undeclare everything."""

    def __init__(
        self,
        session: zenoh.Session,
        wire: Wire,
        hand_off: Callable[[RosSample], None],
        skip: tuple[str, str] | None = None,
        max_bytes: int = DEFAULT_MAX_MESSAGE_BYTES,
    ) -> None:
        def on_sample(sample: zenoh.Sample) -> None:
            if sample.kind == zenoh.SampleKind.PUT:
                hand_off(received(sample, max_bytes))

        self.keys: list[str] = []
        self._entities: list[Any] = []
        self._session = session
        self._hand_off = hand_off
        self._max_bytes = max_bytes
        self._cached: list[str] = []  # publication cache selectors (older generation)
        self._timer: threading.Timer | None = None
        try:
            for topic, typename, transient_local in TOPICS:
                if (topic, typename) == skip:
                    continue
                key = wire.subscription(topic, typename, any_type=True)
                self.keys.append(key)
                entity: zenoh.Subscriber[None] | zenoh.ext.AdvancedSubscriber[None]
                if transient_local:
                    history = zenoh.ext.HistoryConfig(detect_late_publishers=True)
                    entity = zenoh.ext.declare_advanced_subscriber(
                        session, key, on_sample, history=history
                    )
                    self._cached.append(publication_cache_selector(wire, key))
                else:
                    entity = session.declare_subscriber(key, on_sample)
                self._entities.append(entity)
            self.query_publication_caches()
            self._timer = threading.Timer(CACHE_QUERY_AGAIN_S, self.query_publication_caches)
            self._timer.daemon = True
            self._timer.start()
        except BaseException:
            self.close()
            raise

    def query_publication_caches(self) -> None:
        """Ask the older generation's publication caches for what they hold; replies go
        to ``hand_off`` like samples (a reply also held by a newer cache is a duplicate
        the topics' rules absorb: a static transform or a list said twice)."""
        query_publication_caches(
            self._session,
            self._cached,
            lambda sample: self._hand_off(received(sample, self._max_bytes)),
        )

    def close(self) -> None:
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None
        for entity in self._entities:
            entity.undeclare()
        self._entities = []


class RobotPublishers:
    """The ROS 2 output's sender (``outputs.Sender``): the publisher thread's publishers,
    in the robot's format and in each form it is answered in (``form``: the worker learns
    them from the robot's samples; two robots of different distros on one router are each
    answered in their own).

    Congestion control is rmw_zenoh's for the QoS we advertise (reliable, keep last 10):
    DROP, as its ``rmw_publisher_data.cpp`` chooses for every keep-last publisher, so a
    subscriber that stops reading costs it samples, never the service a stall."""

    kinds = frozenset({Kind.ROS})

    def __init__(
        self, session: zenoh.Session, wire: Wire, node_name: str, form: FormLearner
    ) -> None:
        self.session = session
        self.wire = wire
        self.node_name = node_name
        self.form = form
        self._publishers: dict[tuple[str, Form], TopicWriter] = {}  # (topic, form)
        self._next_entity_id = 1  # 0 is the node's
        self._node_token = None
        if wire.format is RosFormat.RMW_ZENOH:
            self._node_token = session.liveliness().declare_token(self.node_token_key())

    def _prefix(self, entity_id: int, kind: str) -> str:
        ns = _mangle("/" + self.wire.namespace) if self.wire.namespace else "%"
        return (
            f"@ros2_lv/{self.wire.domain_id}/{self.session.zid()}/0/{entity_id}/{kind}/%/{ns}/"
            f"{_mangle(self.node_name)}"
        )

    def node_token_key(self) -> str:
        return self._prefix(0, "NN")

    def publisher_token_key(
        self, entity_id: int, topic: str, typename: str, wire: Wire | None = None
    ) -> str:
        wire = wire or self.wire
        full_topic = f"/{wire.namespace}{topic}" if wire.namespace else topic
        return (
            f"{self._prefix(entity_id, 'MP')}/{_mangle(full_topic)}/"
            f"{ros2_types.dds_type_name(typename)}/{wire.type_hash(typename)}/"
            f"{QOS_RELIABLE_VOLATILE}"
        )

    def send(self, message: Publication) -> None:
        """Put the message (its ``key`` is the ROS topic) on its topic in every form the
        robot is answered in; the publishers of a form no longer answered in, or of a
        subject gone (no payload), are undeclared."""
        topic, payload, _, typename = message
        forms = self.form.forms
        for key in [k for k in self._publishers if k[0] == topic]:
            if payload is None or key[1] not in forms:
                self._publishers.pop(key).undeclare()
        if payload is None:
            return
        assert typename is not None  # every message for the robot names its type
        for form in forms:
            publisher = self._publishers.get((topic, form))
            if publisher is None:
                publisher = self._publishers[(topic, form)] = self._declare(topic, typename, form)
            publisher.put(payload)

    def _declare(self, topic: str, typename: str, form: Form) -> TopicWriter:
        wire = replace(self.wire, distro=form.distro)
        token = None
        if wire.format is RosFormat.RMW_ZENOH:
            key = self.publisher_token_key(self._next_entity_id, topic, typename, wire)
            token = self.session.liveliness().declare_token(key)
        self._next_entity_id += 1
        data_key = wire.key(topic, typename)
        entity = self.session.declare_publisher(
            data_key, encoding=CDR, congestion_control=zenoh.CongestionControl.DROP
        )
        # rmw_zenoh hashes the liveliness key into the GID (XXH3-128); a SHA-256 prefix
        # of the data key and entity number is as unique, which is all a GID must be.
        gid = hashlib.sha256(f"{data_key}#{self._next_entity_id}".encode()).digest()[:16]
        return TopicWriter(entity, wire, gid, token, form)

    def close(self) -> None:
        for publisher in self._publishers.values():
            publisher.undeclare()
        self._publishers.clear()
        if self._node_token is not None:
            self._node_token.undeclare()
            self._node_token = None


def _mangle(name: str) -> str:
    """rmw_zenoh's liveliness names: '/' becomes '%'."""
    return name.replace("/", "%")


def robot_topic_writer(
    session: zenoh.Session, key: str, wire: Wire, cache_depth: int | None
) -> TopicWriter:
    """A writer publishing as a robot does (a replayed or a simulated one), with BLOCK: it
    loses nothing. With ``cache_depth``, a transient-local topic as rmw_zenoh publishes
    one: a zenoh-ext advanced publisher with a cache that deep and publisher detection, so
    a subscriber that starts later still gets it."""
    block = zenoh.CongestionControl.BLOCK
    if cache_depth is not None:
        entity: Any = zenoh.ext.declare_advanced_publisher(
            session,
            key,
            encoding=CDR,
            congestion_control=block,
            cache=zenoh.ext.CacheConfig(cache_depth),
            # Sequence numbers order the cache (as rmw_zenoh's publishers do), so the
            # session needs no timestamping enabled.
            sample_miss_detection=zenoh.ext.MissDetectionConfig(
                heartbeat=None, sporadic_heartbeat=None
            ),
            publisher_detection=True,
        )
    else:
        entity = session.declare_publisher(key, encoding=CDR, congestion_control=block)
    return TopicWriter(entity, wire, os.urandom(GID_SIZE))


class TopicWriter:
    """Puts samples on one topic's declared publisher (plain or zenoh-ext advanced) as the
    robot's format wants them: in rmw_zenoh's, each with its attachment in the robot's
    layout, numbered from 1."""

    def __init__(
        self, entity: Any, wire: Wire, gid: bytes, token: Any = None, form: Form | None = None
    ) -> None:
        self._entity = entity
        self._rmw = wire.format is RosFormat.RMW_ZENOH
        self.gid = gid
        self.form = form or Form(wire.distro)
        self._token = token  # the publisher's liveliness token, if it holds one
        self.sequence_number = 0

    def put(self, payload: bytes) -> None:
        self.sequence_number += 1
        extra = None
        if self._rmw:
            extra = attachment(self.sequence_number, time.time_ns(), self.gid, self.form.attachment)
        self._entity.put(payload, attachment=extra)

    def matched(self) -> bool:
        """Whether a subscriber matches this topic now (zenoh's matching status)."""
        status: Any = self._entity.matching_status
        return bool(status.matching)

    def undeclare(self) -> None:
        self._entity.undeclare()
        if self._token is not None:
            self._token.undeclare()
