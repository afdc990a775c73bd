"""ROS 2 message types against their upstream: the package's `.msg` files are the ROS 2
releases' own bytes (git blob ids pinned to the upstream tags), and their RIHS01 hashes are
the values two independent implementations compute from those files."""

from __future__ import annotations

import hashlib
import json

import pytest

from facing_service.ros2 import types as ros2_types
from facing_service.ros2.output import INTENT, engage_intent

from upstream import STANDARD_MSGS, UPSTREAM, definition


def git_blob_id(data: bytes) -> str:
    """What `git hash-object` says of a file: its identity in the upstream tree."""
    return hashlib.sha1(b"blob %d\0" % len(data) + data).hexdigest()


@pytest.mark.parametrize("typename", list(UPSTREAM))
def test_message_files_are_the_upstream_ros2_releases_bytes(typename):
    path, blob, _ = UPSTREAM[typename]
    assert git_blob_id((ros2_types.MSG_DIR / path).read_bytes()) == blob, (
        f"facing_service/ros2/msg/{path} is not the upstream file (msg/README.md says where from)"
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
