"""A session of a running service kept as MCAP, without ROS: which of the namespace's keys
are kept and under which JSON Schema (the wire contract's, as ``schemas/`` holds them),
and how such a file is told from a ROS 2 bag. Pure.

Each key is a topic of its own (``hri/bodies/ann/facing/base_link``), as ROS topics are
per person, so Foxglove's panels pick one person or all (``hri/bodies/*/facing/*``). A
DELETE (a person gone) is a message on ``DELETES`` naming its key: MCAP has no empty
message. The service's status, asked once a second, is kept under its status key.
"""

from __future__ import annotations

import json
from typing import Any

from ..contract import keys
from ..contract.schemas import json_schemas

#: The MCAP header's profile: a session of ours (a rosbag2's is "ros2").
PROFILE = "facing-service"
DELETES = "zenoh/delete"
DELETE_SCHEMA: dict[str, Any] = {
    "title": "Delete",
    "description": "A DELETE on a key: what was said there is gone (a person lost).",
    "type": "object",
    "properties": {"key": {"type": "string"}},
    "required": ["key"],
}

#: The key's shape under the namespace (``*`` one chunk) -> its payload's schema file.
SHAPES = (
    (("bodies", "*", "pose", "*"), "pose.schema.json"),
    (("bodies", "*", "facing", "*"), "facing_state.schema.json"),
    (("bodies", "*", "engagement", "*"), "engagement_state.schema.json"),
    (("events", "engagement", "*"), "engagement_event.schema.json"),
    (("facing", "*"), "frame_facing.schema.json"),
    (("groups", "*"), "frame_groups.schema.json"),
    (("groups", "*", "*"), "group_state.schema.json"),
    (("gazing", "*"), "frame_gazing.schema.json"),
    (("services", "facing", "*", "status"), "status.schema.json"),
)


def schema_file(namespace: str, key: str) -> str | None:
    """The schema file of what ``key`` carries, or None for a key not kept (not the
    namespace's, or not one of the contract's)."""
    if not key.startswith(namespace + "/"):
        return None
    chunks = tuple(key[len(namespace) + 1 :].split("/"))
    for shape, name in SHAPES:
        same = len(shape) == len(chunks)
        if same and all(s in ("*", c) for s, c in zip(shape, chunks, strict=True)):
            return name
    return None


def schema_bytes(name: str) -> bytes:
    """A schema file's JSON, as the MCAP schema record holds it."""
    schema = DELETE_SCHEMA if name == DELETES else json_schemas()[name]
    return json.dumps(schema, separators=(",", ":")).encode()


def is_input(namespace: str, key: str) -> bool:
    """Whether a key is the service's input (a tracker's poses), which a replay sends."""
    return keys.parse_pose_key(namespace, key) is not None
