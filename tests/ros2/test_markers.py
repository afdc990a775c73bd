"""RViz markers (issue 34): a MarkerArray of two people and their group, encoded by the
service and decoded by rosbags' own CDR (arrays of several markers: alignment inside a
sequence of structs is where encoders go wrong), against the upstream type hash."""

from __future__ import annotations

import math

import pytest

from facing_service.core.engagement import Level
from facing_service.core.groups import Group
from facing_service.ros2 import types as ros2_types
from facing_service.ros2.markers import COLOURS, MARKER_ARRAY, Drawn, MarkerDrawer

#: visualization_msgs/msg/MarkerArray, identical in Humble and Jazzy (common_interfaces).
UPSTREAM_HASH = "RIHS01_86cb8800b6fb05b5eff1abd7a56f62a5641d3ae9a1c29e78e67e704f1d067dcf"


def yaw(deg: float) -> tuple[float, float, float, float]:
    return (0.0, 0.0, math.sin(math.radians(deg) / 2), math.cos(math.radians(deg) / 2))


ANN = Drawn("ann", (2.0, 0.6, 0.0), yaw(-90), Level.ENGAGED, 20.0, 12.0, 2.1)
BOB = Drawn("bob<script>", (2.0, -0.6, 0.0), yaw(90), Level.DISENGAGED, 20.0, None, None)
GROUP = Group(4, frozenset({"ann", "bob<script>", ""}), True, (2.0, 0.0))


def decode(payload: bytes):
    return ros2_types.deserialize(payload, MARKER_ARRAY).markers


def test_the_marker_array_type_is_upstreams():
    assert ros2_types.type_hash(MARKER_ARRAY) == UPSTREAM_HASH


def test_two_people_and_their_group_decode_as_drawn():
    markers = decode(MarkerDrawer().draw("base_link", (5, 0), [ANN, BOB], [GROUP]))
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
    drawer.draw("base_link", (5, 0), [ANN, BOB], [GROUP])
    markers = decode(drawer.draw("base_link", (6, 0), [ANN], []))
    deleted = sorted((m.ns, m.id) for m in markers if m.action == 2)
    assert deleted == [("group/4", 0), ("group/4", 1)] + [
        ("person/bob<script>", i) for i in range(3)
    ]
    assert sorted((m.ns, m.id) for m in markers if m.action == 0) == [
        ("person/ann", i) for i in range(3)
    ]
    assert [m for m in decode(drawer.draw("base_link", (7, 0), [ANN], [])) if m.action == 2] == []
