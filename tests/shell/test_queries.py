"""Queries on every output key space, answered from the turn's view in order with the
poses: current state, what-if cones, refusals, and what an unmatched query still says."""

from __future__ import annotations

import pytest

from loopback import get, send
from poses import pose_json
from service_rig import FRAME_KEY, NAMESPACE, body_key, pose_key


def test_queries_answer_current_state_and_what_if_thresholds(rig):
    service, client, rec = rig()
    send(client, pose_key("a"), pose_json("a", "cam", off_deg=10.0))
    send(client, pose_key("b"), pose_json("b", "cam", x=3.0, y=1.0, off_deg=-30.0))
    rec.wait_for(lambda i: i.key == FRAME_KEY and i.value["bodies_tracked"] == ["a", "b"])

    replies = dict(get(client, f"{NAMESPACE}/bodies/*/facing/cam"))
    assert set(replies) == {body_key("a"), body_key("b")}
    assert replies[body_key("a")]["facing"] and not replies[body_key("b")]["facing"]

    (single,) = get(client, body_key("b"))
    assert single[0] == body_key("b") and single[1]["angle_deg"] == pytest.approx(30.0)

    (frame,) = get(client, f"{NAMESPACE}/facing/**")
    assert frame == (FRAME_KEY, rec.on(FRAME_KEY)[-1].value)

    everything = dict(get(client, f"{NAMESPACE}/**"))
    status = f"{NAMESPACE}/services/facing/{service.settings.instance}/status"
    engagement = {f"{NAMESPACE}/bodies/{b}/engagement/cam" for b in ("a", "b")}
    scene = {f"{NAMESPACE}/groups/cam", f"{NAMESPACE}/gazing/cam"}
    assert set(everything) == {body_key("a"), body_key("b"), FRAME_KEY, status, *engagement, *scene}

    what_if = dict(get(client, f"{NAMESPACE}/bodies/*/facing/cam?threshold_deg=35"))
    assert what_if[body_key("b")]["facing"] and what_if[body_key("b")]["threshold_deg"] == 35.0
    (frame35,) = get(client, f"{FRAME_KEY}?threshold_deg=35")
    assert frame35[1]["bodies_facing"] == ["a", "b"]
    (frame5,) = get(client, f"{FRAME_KEY}?threshold_deg=5")
    assert frame5[1]["bodies_facing"] == []

    # the what-ifs left the service's state and decisions unchanged
    assert dict(get(client, f"{NAMESPACE}/bodies/*/facing/cam")) == replies
    assert get(client, FRAME_KEY)[0][1]["bodies_facing"] == ["a"]
    # a frame this service does not track (here a fixed base frame): said, not left unanswered
    ((kind, error),) = get(client, f"{NAMESPACE}/facing/map")
    assert (kind, error["error"]) == ("error", "unknown_frame") and "cam" in error["detail"]
    assert service.status().counters["queries_refused"] == 0


@pytest.mark.parametrize(
    "parameters",
    [
        "threshold_deg=abc",
        "threshold_deg=0",
        "threshold_deg=180",
        "threshold_deg=nan",
        "threshold_deg=inf",
        "threshold_deg=",
        "treshold_deg=30",
    ],
)
def test_bad_query_parameter_gets_an_error_reply(rig, parameters):
    _, client, _ = rig()
    replies = get(client, f"{FRAME_KEY}?{parameters}")
    assert len(replies) == 1 and replies[0][0] == "error"
    assert replies[0][1]["error"] == "bad_parameter" and replies[0][1]["detail"]


def test_a_query_on_a_body_not_tracked_beside_others_says_so(rig):
    """A concrete body's key in a frame where others are: "not_tracked" (not silence,
    which would read as "no service", and not "empty_frame", which would be false)."""
    _, client, rec = rig()
    send(client, pose_key("a"), pose_json("a", "cam"))
    rec.wait_for(lambda i: i.key == FRAME_KEY and i.value["bodies_tracked"] == ["a"])
    ((kind, error),) = get(client, f"{NAMESPACE}/bodies/b/facing/cam")
    assert (kind, error["error"]) == ("error", "not_tracked") and "'cam'" in error["detail"]


def test_a_what_if_cone_on_engagement_is_refused_not_ignored(rig):
    """A defect found: ``threshold_deg`` on an engagement query was parsed, a
    re-decision computed and thrown away: the levels answered as if it were not there.
    Engagement is worked out over time (a score, dwell), not re-decided per query: the
    parameter is refused there, as on groups and who faces whom."""
    _, client, rec = rig()
    send(client, pose_key("a"), pose_json("a", "cam", off_deg=10.0))
    rec.wait_for(lambda i: i.key == FRAME_KEY and i.value["bodies_tracked"] == ["a"])
    replies = get(client, f"{NAMESPACE}/bodies/*/engagement/cam?threshold_deg=35")
    assert [kind for kind, _ in replies] == ["error"], replies
    assert replies[0][1]["error"] == "bad_parameter"
    assert "not to engagement" in replies[0][1]["detail"]
