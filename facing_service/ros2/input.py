"""A ROS 2 robot's people, read straight off zenoh: the routing of each sample, decoded
with rosbags, into ``People`` (pure; the subscriptions are the shell's, ``shell.ros_bus``).

Topics read (under ``--ros-namespace``, in ``--ros-format``):

    /tf, /tf_static                          tf2_msgs/msg/TFMessage
    /humans/{bodies,faces,persons}/tracked   hri_msgs/msg/IdsList
    /humans/persons/<id>/{face_id,body_id}   std_msgs/msg/String

``/tf_static`` and the person topics are transient-local in ROS 2, and a service started
after the robot gets them from the publishers' caches, of either generation:

- advanced publishers' caches (rmw_zenoh since Humble 0.1.2 and Jazzy 0.2.2,
  zenoh-bridge-ros2dds since 1.5.1): read by zenoh-ext advanced subscribers with history
  and late-publisher detection;
- ``PublicationCache`` queryables (rmw_zenoh Humble 0.1.0-0.1.1 and Jazzy 0.2.0-0.2.1 on
  ``<zenoh id>/<key>``; the bridge up to 1.5.0 on ``<key>/@ros2_pub_cache/<zenoh id>``):
  queried once at start and once more after ``shell.ros_bus.CACHE_QUERY_AGAIN_S`` (a
  peer discovers the others in a moment), as those releases' own late joiners did,
  accepting replies on any key (they come on the sample's own key).

``/tf`` and the body and face lists stream: plain subscribers.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any

from ..contract.poses import Rejected, Rejection
from ..contract.robot import DEFAULT_MAX_MESSAGE_BYTES
from ..contract.stamps import Time
from ..core.tf.geometry import RigidTransform
from . import types as ros2_types
from .people import KINDS, PERSON_LINKS, People, TfInput, Update
from .wire import RosFormat, Wire

#: (topic pattern, type, transient-local?)
TOPICS = (
    ("/tf", ros2_types.TF_MESSAGE, False),
    ("/tf_static", ros2_types.TF_MESSAGE, True),
    ("/humans/bodies/tracked", ros2_types.IDS_LIST, False),
    ("/humans/faces/tracked", ros2_types.IDS_LIST, False),
    ("/humans/persons/tracked", ros2_types.IDS_LIST, True),
    ("/humans/persons/*/face_id", ros2_types.STRING, True),
    ("/humans/persons/*/body_id", ros2_types.STRING, True),
)


@dataclass(frozen=True, slots=True)
class RosSample:
    """A sample from one of the robot's topics, as the zenoh callback hands it over."""

    key: str
    payload: bytes
    attachment: bytes | None = None  # rmw_zenoh's: its form is learned from it
    size: int = 0  # of a payload too large to be copied (then ``payload`` is empty)


def route(
    people: People,
    wire: Wire,
    sample: RosSample,
    max_bytes: int = DEFAULT_MAX_MESSAGE_BYTES,
    received_s: float | None = None,
    publisher: bytes | None = None,
) -> Update | Rejected:
    """Decode one sample, received at ``received_s`` (the caller's clock) from
    ``publisher`` (its GID, when its attachment says), and apply it to ``people``; never
    raises on any input."""
    read = reading(wire, sample.key)
    if isinstance(read, Rejected):
        return read
    if sample.size > max_bytes:  # refused before decoding: a 104 MB TFMessage took 2.2 GB
        return Rejected(Rejection.PAYLOAD_TOO_LARGE, f"{sample.size} bytes > {max_bytes}")
    topic, typename = read
    try:
        message = ros2_types.deserialize(sample.payload, typename)
    except Exception as error:  # rosbags raises several kinds on truncated or bad CDR
        return Rejected(Rejection.MALFORMED_CDR, f"{type(error).__name__}: {error}"[:200])
    if typename == ros2_types.TF_MESSAGE:
        return people.on_tf(
            tf_inputs(message),
            static=topic == "/tf_static",
            publisher=publisher,
            received_s=received_s,
        )
    if typename == ros2_types.IDS_LIST:
        return people.on_tracked(topic, list(message.ids))
    _, _, _, person_id, link = topic.split("/")
    return people.on_person_link(person_id, link, message.data)


@lru_cache(maxsize=4096)
def reading(wire: Wire, key: str) -> tuple[str, str] | Rejected:
    """The topic and type a key is read as, or why it is refused. Remembered: a robot
    repeats a handful of keys (a tenth of the ROS path's worker time went here)."""
    topic = wire.topic_of(key)
    typename = _typename(topic)
    if topic is None or typename is None:
        return Rejected(Rejection.INVALID_KEY, "not a topic this service reads")
    if reason := wire.check(key, typename):
        return Rejected(Rejection.TYPE_MISMATCH, reason)
    return topic, typename


def _typename(topic: str | None) -> str | None:
    if topic is None:
        return None
    if topic in ("/tf", "/tf_static"):
        return ros2_types.TF_MESSAGE
    if topic in KINDS:
        return ros2_types.IDS_LIST
    parts = topic.split("/")
    if len(parts) == 5 and parts[1:3] == ["humans", "persons"] and parts[4] in PERSON_LINKS:
        return ros2_types.STRING
    return None


def tf_inputs(message: Any) -> list[TfInput]:
    """A TFMessage's transforms as plain values (a stamp our outputs cannot carry is
    None, refused by ``People``)."""
    inputs = []
    for t in message.transforms:
        tr, rot = t.transform.translation, t.transform.rotation
        inputs.append(
            TfInput(
                t.header.frame_id,
                t.child_frame_id,
                Time.checked(t.header.stamp.sec, t.header.stamp.nanosec),
                RigidTransform((tr.x, tr.y, tr.z), (rot.x, rot.y, rot.z, rot.w)),
            )
        )
    return inputs


def publication_cache_selector(wire: Wire, key: str) -> str:
    """Where the older generation's publication caches of a subscription key answer."""
    if wire.format is RosFormat.BRIDGE:
        return f"{key}/@ros2_pub_cache/*"
    return f"*/{key}"
