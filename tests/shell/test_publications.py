"""What the service says, from the tracker's changes and state: keys, payloads, order."""

from __future__ import annotations

import json

import pytest

from facing_service.contract.keys import BodyRef
from facing_service.contract.poses import Stamp
from facing_service.contract.schemas import (
    EngagementEvent,
    EngagementState,
    FacingState,
    FrameFacing,
)
from facing_service.contract.stamps import Time
from facing_service.core.engagement import Level, Zone
from facing_service.core.records import BodyState, Changes, EngagementUpdate
from facing_service.ros2.output import RosMessage
from facing_service.shell.outbox import Kind, Publication
from facing_service.shell.publications import (
    Speaker,
    publications,
    query_replies,
    ros_publications,
    threshold_parameter,
)

ME = "host-1"


def at(body: str) -> BodyRef:
    return BodyRef(frame_id="cam", body_id=body)


def state(body: str, facing: bool = True) -> BodyState:
    return BodyState(
        at(body), Time.of(5, 6), facing, 3.0, 2.0, (2.0, 0.1, 0.0), 20.0, (-2.0, 0.1, 0.0), 0.0
    )


def update(body: str, level: Level, previous: Level | None) -> EngagementUpdate:
    return EngagementUpdate(at(body), Time.of(5, 6), level, 0.8, Zone.SOCIAL, Time.of(4), previous)


def frame(facing: list[str], tracked: list[str]) -> FrameFacing:
    return FrameFacing(
        frame_id="cam", stamp=Stamp(sec=5, nanosec=6), bodies_facing=facing, bodies_tracked=tracked
    )


def test_one_call_is_said_in_publishing_order_on_the_contract_keys():
    changes = Changes(
        results=[state("a"), state("b", facing=False)],
        engagement=[
            update("a", Level.ENGAGING, Level.DISENGAGED),  # a change: state, then event
            update("b", Level.DISENGAGED, None),  # a periodic state: no event
            update("c", Level.UNKNOWN, Level.ENGAGED),  # lost: an event, no state
        ],
        lost=[at("c")],
        frames=[frame(["a"], ["a", "b"])],
    )
    said = publications(changes, Speaker("hri", ME))
    put, delete = True, False
    assert [(p.key, p.kind, p.payload is not None) for p in said] == [
        ("hri/bodies/a/facing/cam", Kind.RESULT, put),
        ("hri/bodies/b/facing/cam", Kind.RESULT, put),
        ("hri/bodies/a/engagement/cam", Kind.ENGAGEMENT, put),
        ("hri/events/engagement/cam", Kind.EVENT, put),
        ("hri/bodies/b/engagement/cam", Kind.ENGAGEMENT, put),
        ("hri/events/engagement/cam", Kind.EVENT, put),
        ("hri/bodies/c/facing/cam", Kind.RESULT, delete),
        ("hri/bodies/c/engagement/cam", Kind.ENGAGEMENT, delete),
        ("hri/facing/cam", Kind.FRAME, put),
    ]
    models = {
        Kind.RESULT: FacingState,
        Kind.ENGAGEMENT: EngagementState,
        Kind.EVENT: EngagementEvent,
        Kind.FRAME: FrameFacing,
    }
    for p in said:
        if p.payload is None:
            continue
        decoded = models[p.kind].model_validate_json(p.payload)
        assert decoded.instance == ME
    events = [EngagementEvent.model_validate_json(p.payload) for p in said if p.kind is Kind.EVENT]
    assert [(e.body_id, e.previous, e.level) for e in events] == [
        ("a", "DISENGAGED", "ENGAGING"),
        ("c", "ENGAGED", "UNKNOWN"),
    ]
    first = FacingState.model_validate_json(said[0].payload)
    assert (first.body_id, first.frame_id, first.facing, first.stamp.nanosec) == (
        "a",
        "cam",
        True,
        6,
    )
    assert json.loads(said[-1].payload)["bodies_facing"] == ["a"]


def test_nothing_changed_says_nothing():
    assert publications(Changes(), Speaker("hri", ME)) == []


def test_ros_messages_travel_as_ros_publications():
    said = ros_publications([RosMessage("/intents", "hri_actions_msgs/msg/Intent", b"\x00")])
    assert said == [Publication("/intents", b"\x00", Kind.ROS, "hri_actions_msgs/msg/Intent")]


def test_query_replies_per_space():
    states, frames = [state("a")], [frame([], ["a"])]
    engagements = [update("a", Level.ENGAGED, None)]

    def replies(space):
        return query_replies(space, Speaker("r1/hri", ME), states, frames, engagements)

    ((key, payload),) = replies("facing")
    assert key == "r1/hri/bodies/a/facing/cam"
    assert FacingState.model_validate_json(payload).instance == ME
    ((key, payload),) = replies("frame")
    assert key == "r1/hri/facing/cam"
    assert FrameFacing.model_validate_json(payload).bodies_tracked == ["a"]
    ((key, payload),) = replies("engagement")
    assert key == "r1/hri/bodies/a/engagement/cam"
    assert EngagementState.model_validate_json(payload).level == "ENGAGED"
    with pytest.raises(ValueError, match="unknown query space 'x'"):
        replies("x")


@pytest.mark.parametrize(
    ("parameters", "expected"),
    [
        ({}, None),
        ({"threshold_deg": "30"}, 30.0),
        ({"threshold_deg": "0.5", "_time": "x"}, 0.5),  # zenoh's own parameters pass
    ],
)
def test_threshold_parameter(parameters, expected):
    assert threshold_parameter(parameters) == expected


@pytest.mark.parametrize(
    ("parameters", "message"),
    [
        ({"threshold_deg": "wide"}, "threshold_deg must be a number, got 'wide'"),
        ({"threshold_deg": "180"}, r"threshold_deg must be in \(0, 180\), got '180'"),
        ({"threshold_deg": "nan"}, r"must be in \(0, 180\)"),
        ({"threshold_deg": "0"}, r"must be in \(0, 180\)"),
        ({"threshold": "30"}, "unknown parameter.s. threshold; known: threshold_deg"),
    ],
)
def test_threshold_parameter_refusals_say_why(parameters, message):
    with pytest.raises(ValueError, match=message):
        threshold_parameter(parameters)


def test_a_groups_members_are_said_in_natural_order():
    """A defect found: members were sorted as text (p12, p13, p4)."""
    from facing_service.contract.stamps import Time
    from facing_service.core.social.groups import Group
    from facing_service.core.social.scene import ROBOT
    from facing_service.shell.publications import group_state

    group = Group(3, frozenset({"p12", "p4", "p13", ROBOT}), True, (1.0, 0.0))
    said = group_state(group, Time.of(7, 5))
    assert said.members == ["p4", "p12", "p13"] and said.robot
    # each group says when: an event arriving late can be told from a current one
    assert (said.stamp.sec, said.stamp.nanosec) == (7, 5)
