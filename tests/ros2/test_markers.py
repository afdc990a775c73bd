"""RViz markers: a MarkerArray of two people and their group, encoded by the
service and decoded by rosbags' own CDR (arrays of several markers: alignment inside a
sequence of structs is where encoders go wrong), against the upstream type hash."""

from __future__ import annotations

import hashlib
import math
from pathlib import Path

import pytest

from facing_service.contract.levels import Level
from facing_service.contract.stamps import Time
from facing_service.core.social.groups import Group
from facing_service.ros2 import types as ros2_types
from facing_service.ros2.markers import COLOURS, MARKER_ARRAY, MarkerDrawer, PersonMarker

#: visualization_msgs/msg/MarkerArray, identical in Humble and Jazzy (common_interfaces).
UPSTREAM_HASH = "RIHS01_86cb8800b6fb05b5eff1abd7a56f62a5641d3ae9a1c29e78e67e704f1d067dcf"


def yaw(deg: float) -> tuple[float, float, float, float]:
    return (0.0, 0.0, math.sin(math.radians(deg) / 2), math.cos(math.radians(deg) / 2))


ANN = PersonMarker("ann", (2.0, 0.6, 0.0), yaw(-90), Level.ENGAGED, 20.0, 12.0, 2.1)
BOB = PersonMarker("bob<script>", (2.0, -0.6, 0.0), yaw(90), Level.DISENGAGED, 20.0, None, None)
GROUP = Group(4, frozenset({"ann", "bob<script>", ""}), True, (2.0, 0.0))


def decode(payload: bytes):
    return ros2_types.deserialize(payload, MARKER_ARRAY).markers


def test_the_marker_array_type_is_upstreams():
    assert ros2_types.type_hash(MARKER_ARRAY) == UPSTREAM_HASH


def test_two_people_and_their_group_decode_as_drawn():
    markers = decode(MarkerDrawer().draw("base_link", Time.of(5), [ANN, BOB], [GROUP]))
    by = {(m.ns, m.id): m for m in markers}
    assert sorted(by) == [
        ("group/4", 0), ("group/4", 1),
        ("person/ann", 0), ("person/ann", 1), ("person/ann", 2),
        ("person/bob<script>", 0), ("person/bob<script>", 1), ("person/bob<script>", 2),
    ]  # fmt: skip
    assert all(m.header.frame_id == "base_link" and m.action == 0 for m in markers)
    cone, arrow, text = (by[("person/ann", i)] for i in range(3))
    assert (cone.type, arrow.type, text.type) == (11, 0, 9)  # TRIANGLE_LIST, ARROW, TEXT
    assert len(cone.points) == 24 and (cone.pose.position.x, cone.pose.position.y) == (2.0, 0.6)
    assert (text.color.r, text.color.g, text.color.b) == pytest.approx(COLOURS[Level.ENGAGED])
    assert text.text == "ann ENGAGED 12° 2.1 m"
    assert by[("person/bob<script>", 2)].text == "bob<script> DISENGAGED - -"
    assert by[("person/bob<script>", 1)].color.r == pytest.approx(COLOURS[Level.DISENGAGED][0])
    lines = by[("group/4", 1)]
    ends = {(p.x, p.y) for p in lines.points}
    assert {(2.0, 0.6), (2.0, -0.6), (0.0, 0.0), (2.0, 0.0)} == ends  # the robot's too


def test_who_leaves_is_deleted_by_id_and_nothing_else():
    drawer = MarkerDrawer()
    drawer.draw("base_link", Time.of(5), [ANN, BOB], [GROUP])
    markers = decode(drawer.draw("base_link", Time.of(6), [ANN], []))
    deleted = sorted((m.ns, m.id) for m in markers if m.action == 2)
    assert deleted == [("group/4", 0), ("group/4", 1)] + [
        ("person/bob<script>", i) for i in range(3)
    ]
    assert sorted((m.ns, m.id) for m in markers if m.action == 0) == [
        ("person/ann", i) for i in range(3)
    ]
    assert [
        m for m in decode(drawer.draw("base_link", Time.of(7), [ANN], [])) if m.action == 2
    ] == []


# -- the definition, checked against upstream common_interfaces --------------------------

UPSTREAM_MSGS = Path(__file__).resolve().parents[1] / "upstream_msgs"
JAZZY, HUMBLE = "common_interfaces-5.3.5", "common_interfaces-4.2.4"
#: git blob ids at ros2/common_interfaces 5.3.5 (b8539bfd, Jazzy) and 4.2.4 (53761cba,
#: Humble): `git rev-parse <tag>:<path>`. Humble's files are those whose text differs.
BLOBS = {
    (JAZZY, "visualization_msgs/msg/MarkerArray.msg"): "dd0fab432abc3cc14ce9c24c12975867c1aca905",
    (JAZZY, "visualization_msgs/msg/Marker.msg"): "eb9938a11a039098037b68b5f7d781b9c4ec4620",
    (JAZZY, "visualization_msgs/msg/UVCoordinate.msg"): "d48b0f293e99b7a660213e052d1532bc36005708",
    (JAZZY, "visualization_msgs/msg/MeshFile.msg"): "f7c43398365d5849158ee6cc08567b8d87047580",
    (JAZZY, "std_msgs/msg/Header.msg"): "6966bb98863c237131a2bd2822298df9511ce948",
    (JAZZY, "std_msgs/msg/ColorRGBA.msg"): "182dbc8349abec122d95436cb840906503f569f2",
    (JAZZY, "geometry_msgs/msg/Pose.msg"): "277e2f0179a64cd3e17e31502e3d8a074ace7064",
    # the same blob at 4.2.4 (Humble): where the robot should stand
    (JAZZY, "geometry_msgs/msg/PoseStamped.msg"): "2b43935ed33b384937142aaf3aae085cdcb9ea5e",
    (JAZZY, "geometry_msgs/msg/Point.msg"): "f1d3a71a853c668f066de795ba5e0f4458f3f1c0",
    (JAZZY, "geometry_msgs/msg/Quaternion.msg"): "96d392779a286cc3f4c83d80962236f5ea42c884",
    (JAZZY, "geometry_msgs/msg/Vector3.msg"): "b54588e117c4632f551c221fbc33df8f958804bf",
    (JAZZY, "sensor_msgs/msg/CompressedImage.msg"): "12a724d564752fe076b394114aeaeca9e79b1f67",
    (HUMBLE, "visualization_msgs/msg/Marker.msg"): "53811d5f4264996ea7e64fd8834d69c39bc67b4e",
    (HUMBLE, "sensor_msgs/msg/CompressedImage.msg"): "0b0b4f537974d33aa9ffd8edaaac48bd0c237957",
}
#: rcl_interfaces' builtin_interfaces (Time, Duration: the same two fields).
BUILTIN = {
    "builtin_interfaces/msg/Time": "int32 sec\nuint32 nanosec\n",
    "builtin_interfaces/msg/Duration": "int32 sec\nuint32 nanosec\n",
}


def test_the_copies_are_upstreams_files():
    for (tag, path), blob in BLOBS.items():
        data = (UPSTREAM_MSGS / tag / path).read_bytes()
        assert hashlib.sha1(b"blob %d\0" % len(data) + data).hexdigest() == blob, (tag, path)
    assert {p.relative_to(UPSTREAM_MSGS).as_posix() for p in UPSTREAM_MSGS.rglob("*.msg")} == {
        f"{tag}/{path}" for tag, path in BLOBS
    }


@pytest.mark.parametrize("release", [JAZZY, HUMBLE])
def test_humble_and_jazzy_marker_arrays_hash_as_the_type_we_send(release):
    """zenoh-ros2-sdk's RIHS01 from upstream's text (Humble's Marker and CompressedImage
    differ in comments only) is the hash of what rosbags encodes for us."""
    from zenoh_ros2_sdk.utils import compute_type_hash_from_msg

    texts = {
        path.removesuffix(".msg"): (UPSTREAM_MSGS / tag / path).read_text()
        for tag, path in BLOBS
        if tag == JAZZY
    }
    texts |= {
        path.removesuffix(".msg"): (UPSTREAM_MSGS / tag / path).read_text()
        for tag, path in BLOBS
        if tag == release
    }
    top = texts.pop(MARKER_ARRAY)
    assert compute_type_hash_from_msg(MARKER_ARRAY, top, texts | BUILTIN) == UPSTREAM_HASH


def test_the_place_to_stand_hashes_as_upstreams_pose_stamped():
    """geometry_msgs/PoseStamped (the join and greet places): zenoh-ros2-sdk's
    RIHS01 from upstream's text is the hash of the type rosbags encodes for us."""
    from zenoh_ros2_sdk.utils import compute_type_hash_from_msg

    from facing_service.ros2 import types as ros2_types
    from facing_service.ros2.output import POSE_STAMPED

    texts = {
        path.removesuffix(".msg"): (UPSTREAM_MSGS / tag / path).read_text()
        for tag, path in BLOBS
        if tag == JAZZY
    }
    top = texts.pop(POSE_STAMPED)
    theirs = compute_type_hash_from_msg(POSE_STAMPED, top, texts | BUILTIN)
    assert theirs == ros2_types.type_hash(POSE_STAMPED)


def test_markers_go_out_at_most_ten_times_a_second_whatever_the_rate():
    from facing_service.config.profiles import tracker_for
    from facing_service.config.settings import Settings
    from facing_service.contract.keys import BodyRef
    from facing_service.contract.poses import decode_pose
    from facing_service.core.records import PoseSample
    from facing_service.core.snapshot import TurnSnapshot
    from facing_service.ros2.markers import MARKERS_TOPIC
    from facing_service.ros2.output import RosOutput

    from poses import pose_json

    tracker = tracker_for(Settings(base_frame="base_link"))
    pose = decode_pose(pose_json("ann", "base_link"), "ann", "base_link", 1 << 16)
    tracker.ingest([PoseSample(BodyRef(frame_id="base_link", body_id="ann"), pose)], 0.0)
    out = RosOutput(rate_hz=40.0, intents=False)
    said = [
        m.topic
        for i in range(40)  # one second of ticks at 40 Hz
        for m in out.tick(i / 40, TurnSnapshot(tracker))
    ]
    assert said.count(MARKERS_TOPIC) == 10
