"""ROS 2 message types against their upstream: the package's `.msg` files are the ROS 2
releases' own bytes (git blob ids pinned to the upstream tags), and their RIHS01 hashes are
the values two independent implementations compute from those files."""

from __future__ import annotations

import hashlib
import json

import pytest

from facing_service import ros2_types
from facing_service.ros2_output import ENGAGEMENT_LEVEL, INTENT, engage_intent

#: typename -> (file in facing_service/msg, git blob id at the upstream tag, RIHS01 hash).
#: Upstream: ros4hri/hri_msgs 2.0.0 (5d52c81f) and ros4hri/hri_actions_msgs 2.0.1
#: (a5909864), branch humble-devel: the ROS 2 packages (msg/README.md).
UPSTREAM = {
    ENGAGEMENT_LEVEL: (
        "hri_msgs/EngagementLevel.msg",
        "0b7090157a4d5d990a66ac4d0009c83a3e41d7d3",
        "RIHS01_275391f46d2e6cc0d21085f8e02dce6a8150baa57539ec99bd9f4e0321443788",
    ),
    ros2_types.IDS_LIST: (
        "hri_msgs/IdsList.msg",
        "cb80145624c949c1f1ffb52fa07b5aff12167674",
        "RIHS01_7e0812d1ac945c98fd3e393568d581ad0ab567f37b24eff633eab778c1bfe62d",
    ),
    INTENT: (
        "hri_actions_msgs/Intent.msg",
        "fb1ea5ca93f80f14764a60efa85edb3ad24a77b5",
        "RIHS01_850d5c0a06aecf153f4cbc75f27fc655d687f93300bcc928a9d21712716fcfaa",
    ),
}
#: ROS 2's own std_msgs/Header and builtin_interfaces/Time (common_interfaces,
#: rcl_interfaces), for the SDK's hash of types that nest a Header.
STANDARD_MSGS = {
    "std_msgs/msg/Header": "builtin_interfaces/Time stamp\nstring frame_id\n",
    "builtin_interfaces/msg/Time": "int32 sec\nuint32 nanosec\n",
}


def definition(typename: str) -> str:
    return (ros2_types.MSG_DIR / UPSTREAM[typename][0]).read_text()


def git_blob_id(data: bytes) -> str:
    """What `git hash-object` says of a file: its identity in the upstream tree."""
    return hashlib.sha1(b"blob %d\0" % len(data) + data).hexdigest()


@pytest.mark.parametrize("typename", list(UPSTREAM))
def test_message_files_are_the_upstream_ros2_releases_bytes(typename):
    path, blob, _ = UPSTREAM[typename]
    assert git_blob_id((ros2_types.MSG_DIR / path).read_bytes()) == blob, (
        f"facing_service/msg/{path} is not the upstream file (msg/README.md says where from)"
    )


def test_every_registered_message_file_is_pinned():
    registered = {f"{p.parent.name}/msg/{p.stem}" for p in ros2_types.MSG_DIR.glob("*/*.msg")}
    assert registered == set(UPSTREAM)


@pytest.mark.parametrize("typename", list(UPSTREAM))
def test_type_hashes_are_the_upstream_values_by_two_implementations(typename):
    from zenoh_ros2_sdk.utils import compute_type_hash_from_msg

    _, _, pinned = UPSTREAM[typename]
    assert ros2_types.type_hash(typename) == pinned  # rosbags
    assert compute_type_hash_from_msg(typename, definition(typename), STANDARD_MSGS) == pinned


def test_the_engage_intent_is_filled_as_hri_engagement_fills_it():
    """hri_engagement (humble-devel, engagement_node.py): ``intent = ENGAGE_WITH`` and
    ``data = {"recipient": <person id>}``; the rest from the upstream constants."""
    message = ros2_types.deserialize(engage_intent("p1").payload, INTENT)
    assert message.intent == "__intent_engage_with__"  # Intent.msg 2.0.1, unquoted constant
    assert json.loads(message.data) == {"recipient": "p1"}
    assert message.source == "p1"
    assert message.modality == "__modality_other__"
    assert (message.priority, message.confidence) == (128, 1.0)
