"""Zenoh keys of ROS 2 topics, in the two formats a ROS 2 robot puts on zenoh.

- ``rmw_zenoh`` (ROS 2's zenoh middleware): ``<domain>/<topic>/<dds type>/<type hash>``,
  e.g. ``0/tf/tf2_msgs::msg::dds_::TFMessage_/RIHS01_e369d0f0...``; the topic keeps its
  inner slashes (``0/humans/faces/tracked/...``). Payload: CDR with its encapsulation
  header; each sample carries an attachment (sequence number, source timestamp, GID) that
  input may ignore and rmw_zenoh's subscriptions require.
- ``bridge`` (zenoh-bridge-ros2dds, for DDS robots): the topic without its leading slash,
  under the bridge's namespace if it has one (``tf``, ``bot1/tf``); raw CDR, no attachment.

A ROS namespace (``--ros-namespace``) prefixes every topic, as a remap or the bridge's
namespace would.

What differs between rmw_zenoh's releases (read in ros2-gbp/rmw_zenoh-release, tags
``upstream/<version>``; Humble is 0.1.x, Jazzy 0.2.x, Kilted 0.6.x, Rolling 0.7 and later):

- the type hash in keys and liveliness tokens: Humble has none and writes the literal
  ``TypeHashNotSupported``; Jazzy and later write ``RIHS01_<sha256>``. A subscription's
  key holds the hash, so a publisher in the other form is never heard (``Distro``);
- the attachment (``attachment_helpers.cpp``): since Humble 0.1.2 and Jazzy 0.2.4 three
  zenoh-ext serialized fields, 33 bytes; before, each field preceded by its name
  (``Attachment.KEYED``), which a newer subscription cannot parse, nor an older one ours;
- the default durability behind an empty QoS field: transient-local before Humble 0.1.2
  and Jazzy 0.2.3, volatile since, so a QoS string says every field (``QOS_RELIABLE_VOLATILE``);
- transient-local caches: a ``PublicationCache`` queried on ``*/<key>`` up to Humble
  0.1.1 and Jazzy 0.2.1, an advanced publisher's cache since (``ros2.input``).

Pure: builds and parses strings and bytes, decides nothing else.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable
from dataclasses import dataclass
from enum import Enum
from functools import lru_cache

from zenoh import ZBytes
from zenoh.ext import Int64, ZDeserializeError, z_deserialize, z_serialize

from ..contract.robot import Distro, RosFormat
from . import types as ros2_types

__all__ = ["Distro", "RosFormat"]  # with the wire's own names below; see contract.robot

HASH_NOT_SUPPORTED = "TypeHashNotSupported"


@lru_cache(maxsize=4096)
def distro_of(key: str) -> Distro | None:
    """The form an rmw_zenoh data key is in, from its last chunk (None: neither)."""
    last = key.rpartition("/")[2]
    if last == HASH_NOT_SUPPORTED:
        return Distro.HUMBLE
    return Distro.JAZZY if last.startswith("RIHS01_") else None


@dataclass(frozen=True)
class Wire:
    """Where a robot's topics are on zenoh: its format, domain and namespace."""

    format: RosFormat = RosFormat.RMW_ZENOH
    domain_id: int = 0
    namespace: str = ""  # ROS namespace or bridge namespace, without slashes around
    distro: Distro = Distro.JAZZY  # the type hash form of the keys this wire writes

    def describe(self) -> str:
        """In words, as the commands that publish a robot's topics say where they go:
        ``rmw_zenoh format (domain 0, no namespace, Jazzy's keys ...)``."""
        where = f"domain {self.domain_id}, " if self.format is RosFormat.RMW_ZENOH else ""
        namespace = f"namespace '{self.namespace}'" if self.namespace else "no namespace"
        form = f", {self.distro.describe()}" if self.format is RosFormat.RMW_ZENOH else ""
        return f"{self.format.value} format ({where}{namespace}{form})"

    def type_hash(self, typename: str) -> str:
        """What this wire writes for a type's hash, in data keys and liveliness tokens."""
        if self.distro is Distro.HUMBLE:
            return HASH_NOT_SUPPORTED
        return ros2_types.type_hash(typename)

    def _topic(self, topic: str) -> str:
        topic = topic.strip("/")
        return f"{self.namespace}/{topic}" if self.namespace else topic

    def key(self, topic: str, typename: str) -> str:
        """The key a message of ``typename`` on ``topic`` is published on."""
        if self.format is RosFormat.BRIDGE:
            return self._topic(topic)
        name = ros2_types.dds_type_name(typename)
        return f"{self.domain_id}/{self._topic(topic)}/{name}/{self.type_hash(typename)}"

    def subscription(self, topic_pattern: str, typename: str, *, any_type: bool = False) -> str:
        """What to subscribe to for a topic (``*`` allowed in chunks), any type hash: the
        hash is checked per sample (``check``), so a mismatch is counted, not unseen.
        ``any_type``: any type name too (the service's input: a robot publishing another
        type on the topic is then counted as ``type_mismatch``, not unseen)."""
        if self.format is RosFormat.BRIDGE:
            return self._topic(topic_pattern)
        name = "*" if any_type else ros2_types.dds_type_name(typename)
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


@dataclass(frozen=True)
class Where:
    """Where a key says a topic is: the settings that read it."""

    topic: str  # with its leading slash
    format: str  # rmw_zenoh or bridge
    domain: int | None  # rmw_zenoh only
    namespace: str
    distro: Distro | None  # rmw_zenoh only (None: an unknown type hash)

    def flags(self) -> str:
        said = [f"--ros-format {self.format}"]
        if self.domain is not None:
            said.append(f"--ros-domain-id {self.domain}")
        if self.namespace:
            said.append(f"--ros-namespace {self.namespace}")
        return " ".join(said)

    def describe(self) -> str:
        if self.format == "bridge":
            return "bridge" + (f", namespace {self.namespace}" if self.namespace else "")
        ns = f", namespace {self.namespace}" if self.namespace else ""
        form = self.distro.describe() if self.distro else "an unknown type hash"
        return f"rmw_zenoh, domain {self.domain}{ns}, {form}"


def where(key: str, topics: Iterable[str]) -> Where | None:
    """Where a key of one of ``topics`` (without their leading slash) says it is, in
    either format (None: none of them, or no domain where rmw_zenoh's keys start)."""
    chunks = key.split("/")
    rmw = len(chunks) >= 4 and "::msg::dds_::" in chunks[-2]
    body = chunks[1:-2] if rmw else chunks
    for topic in sorted(topics, key=lambda t: -t.count("/")):
        parts = topic.split("/")
        if body[-len(parts) :] == parts:
            namespace = "/".join(body[: -len(parts)])
            if not rmw:
                return Where("/" + topic, "bridge", None, namespace, None)
            if not chunks[0].isdigit():
                return None
            return Where("/" + topic, "rmw_zenoh", int(chunks[0]), namespace, distro_of(key))
    return None


GID_SIZE = 16


class Attachment(str, Enum):
    """The layout of rmw_zenoh's per-sample attachment (``attachment_helpers.cpp``):
    zenoh-ext serialized int64 sequence number, int64 source timestamp (ns) and the
    16-byte publisher GID as a sequence (a length byte, then the bytes)."""

    CURRENT = "current"  # the three fields: 33 bytes (Humble >= 0.1.2, Jazzy >= 0.2.4, ...)
    KEYED = "keyed"  # each field after its name (Humble 0.1.0-0.1.1, Jazzy 0.2.0-0.2.3)

    def describe(self) -> str:
        if self is Attachment.KEYED:
            return "keyed fields, as rmw_zenoh before Humble 0.1.2 and Jazzy 0.2.4"
        return "33 bytes, as rmw_zenoh since Humble 0.1.2 and Jazzy 0.2.4"


_KEYED_NAMES = ("sequence_number", "source_timestamp", "source_gid")
_CURRENT_SIZE = 8 + 8 + 1 + GID_SIZE


def attachment(
    sequence_number: int,
    source_timestamp_ns: int,
    gid: bytes,
    layout: Attachment = Attachment.CURRENT,
) -> bytes:
    """rmw_zenoh's attachment (its subscriptions drop a sample without one), serialized
    by zenoh-ext, the serializer rmw_zenoh's own C++ uses."""
    if len(gid) != GID_SIZE:
        raise ValueError(f"a GID is {GID_SIZE} bytes, got {len(gid)}")
    fields: tuple[object, ...] = (Int64(sequence_number), Int64(source_timestamp_ns), gid)
    if layout is Attachment.KEYED:
        fields = tuple(x for pair in zip(_KEYED_NAMES, fields, strict=True) for x in pair)
    return z_serialize(fields).to_bytes()


def read_attachment(data: bytes | None) -> tuple[Attachment, bytes] | None:
    """A robot's attachment's layout and publisher GID (None: none, or neither layout).
    The GID says who published a sample; it is sender-chosen like everything else, so
    it sorts, never authorizes."""
    if data is None:
        return None
    if len(data) == _CURRENT_SIZE and data[16] == GID_SIZE:
        return Attachment.CURRENT, data[17:]
    try:
        fields = z_deserialize(tuple[str, Int64, str, Int64, str, bytes], ZBytes(data))
    except ZDeserializeError:
        return None
    if fields[0::2] != _KEYED_NAMES or len(fields[5]) != GID_SIZE:
        return None
    return Attachment.KEYED, fields[5]


def attachment_layout(data: bytes | None) -> Attachment | None:
    """Which layout a robot's attachment is in (None: none, or neither)."""
    read = read_attachment(data)
    return None if read is None else read[0]


#: rmw_zenoh's QoS string for our publishers, every field written out (an empty field
#: means the reader's default, which changed between releases): reliable (1), volatile
#: (2), keep last (1) 10, infinite deadline, lifespan and liveliness lease.
QOS_RELIABLE_VOLATILE = "1:2:1,10:,:,:,,"


@dataclass(frozen=True)
class Form:
    """The form of rmw_zenoh's a robot uses, and so that our answers take."""

    distro: Distro = Distro.JAZZY
    attachment: Attachment = Attachment.CURRENT

    def describe(self) -> str:
        return f"{self.distro.describe()}, attachments {self.attachment.describe()}"


#: A form other than those already answered in is answered in too once this many samples
#: that decode as their topic's type have shown it (the first form is taken at once).
FORM_EVIDENCE = 10
#: A form not heard for this long, while another is, is no longer answered in.
FORM_FORGET_S = 10.0


class FormLearner:
    """The forms of rmw_zenoh's the robot's publishers use, learned from the keys and
    attachments of what they publish (``--ros-distro auto``) or forced; answering in any
    other form reaches no subscriber.

    Learned from the robot, not from anyone: only samples that decoded as their topic's
    type count (the caller's word), the first form is taken at once, and another needs
    ``FORM_EVIDENCE`` of them; a form silent for ``FORM_FORGET_S`` while another is heard
    is dropped. Two robots of different distros on one router are two forms present at
    once: the service answers in each (``forms``), never flapping between them. At most
    four forms exist (two distros, two attachment layouts), so this state is bounded.

    One writer (the worker, ``learn``); the publisher thread reads ``forms``, replaced
    whole, so it never sees half an update."""

    def __init__(self, forced: Distro | None = None, *, answering: bool = True) -> None:
        """``answering``: the service answers on the robot's topics (``--output ros2``);
        without, what is learned is said as what the robot does, not as an answer."""
        self.forced = forced
        self.answering = answering
        self.forms: tuple[Form, ...] = (Form(forced or Distro.JAZZY),)
        self.heard: dict[Form, tuple[int, float]] = {}  # form -> (samples, last heard)
        self.present: tuple[Form, ...] = ()  # the robot's, as learned
        self.changes = 0  # times the forms answered in changed after the first
        self._weighed = float("-inf")  # when the forms were last weighed (caller's clock)
        self.source = "--ros-distro" if forced else "the default: no robot sample learned yet"

    @property
    def current(self) -> Form:
        """The first form answered in (the one the status names first)."""
        return self.forms[0]

    def learn(self, key: str, layout: Attachment | None, now: float) -> tuple[int, str] | None:
        """One decoded sample of the robot's (its key, and its attachment's layout) at
        ``now`` (the caller's clock); a log level and line when the forms answered in
        changed. Per sample on the hot path: a form already answered in is only counted,
        and the forms are weighed again at most once a second."""
        distro = distro_of(key)
        if distro is None or layout is None:
            return None  # not rmw_zenoh's, or a malformed attachment: nothing learned
        observed = Form(distro, layout)
        heard = self.heard.get(observed)
        self.heard[observed] = (1 if heard is None else heard[0] + 1, now)
        if heard is not None and observed in self.present and now - self._weighed < 1.0:
            return None
        self._weighed = now

        def answered(form: Form) -> bool:
            n, last = self.heard[form]
            taken = form in self.present or n >= FORM_EVIDENCE or not self.present
            return now - last <= FORM_FORGET_S and taken

        present = tuple(dict.fromkeys(f for f in (*self.present, *self.heard) if answered(f)))
        for form, (_, last) in list(self.heard.items()):
            if now - last > FORM_FORGET_S:
                del self.heard[form]  # silent: its evidence starts again from nothing
        if present == self.present:
            return None
        first = not self.present
        self.present = present
        forms = tuple(dict.fromkeys(Form(self.forced or f.distro, f.attachment) for f in present))
        self.changes += not first and forms != self.forms
        self.forms = forms
        said = " and ".join(f.describe() for f in present)
        self.source = "--ros-distro" if self.forced else f"learned from {key}"
        forced = self.forced
        wrong = [f for f in present if forced is not None and f.distro is not forced]
        if wrong and forced is not None:
            return logging.WARNING, (
                f"the robot publishes in rmw_zenoh's form for {wrong[0].distro.describe()} "
                f"({key}), but --ros-distro {forced.value} forces the other: none of "
                "its subscribers will hear our answers"
            )
        how = "as --ros-distro says" if self.forced is not None else f"learned from {key}"
        both = "each of " if len(present) > 1 else ""
        if not self.answering:
            return logging.INFO, f"the robot publishes in rmw_zenoh's form for {said} ({how})"
        return logging.INFO, f"answering the robot in {both}rmw_zenoh's form for {said} ({how})"
