"""No ghosts: what consumers are told stays true when trackers go silent, deletes race
late poses, or the service itself dies."""

from __future__ import annotations

import time

from test_engagement_service import replay

from loopback import get, send, send_delete, wait_until_answered
from poses import pose_json


def test_a_silent_bodys_level_reaches_disengaged_on_time(net):
    """The tracker stops publishing while the body is DISENGAGING: the worker's own clock
    takes it to DISENGAGED after the dwell (0.6 s), long before staleness (10 s here)."""
    _service, ep = net.service(stale_after_s=10.0)
    tracker = net.client(ep)
    events = net.recorder(tracker, "hri/events/engagement/cam")
    wait_until_answered(tracker, "hri/facing/cam")
    replay(tracker, "ann", [0.0] * 60)  # faces 2 s: ENGAGED
    events.wait_for(lambda i: i.value["level"] == "ENGAGED")
    replay(tracker, "ann", [90.0] * 15, start_s=102.0)  # turns away 0.5 s, then silence
    (disengaging,) = events.wait_for(lambda i: i.value["level"] == "DISENGAGING")
    silent_from = time.monotonic()
    (disengaged,) = events.wait_for(lambda i: i.value["level"] == "DISENGAGED", timeout=5)
    took = time.monotonic() - silent_from
    assert took < 2.0, f"DISENGAGED {took:.2f} s after the tracker went silent"
    (state,) = get(tracker, "hri/bodies/ann/engagement/cam")
    assert state[1]["level"] == "DISENGAGED"
    assert disengaged.value["previous"] == "DISENGAGING" and disengaging.value


def test_a_late_pose_never_resurrects_a_deleted_body(net):
    service, ep = net.service()
    tracker = net.client(ep)
    results = net.recorder(tracker, "hri/bodies/*/facing/cam")
    wait_until_answered(tracker, "hri/facing/cam")
    send(tracker, "hri/bodies/bob/pose/cam", pose_json("bob", "cam", sec=5))
    results.wait_for(lambda i: i.kind == "put")
    send_delete(tracker, "hri/bodies/bob/pose/cam")
    send(tracker, "hri/bodies/bob/pose/cam", pose_json("bob", "cam", sec=4))  # late
    send(tracker, "hri/bodies/bob/pose/cam", pose_json("bob", "cam", sec=5))  # repeated
    wait_until_answered(tracker, "hri/facing/cam")  # the worker is past them
    assert get(tracker, "hri/bodies/bob/facing/cam") == []
    assert service.status().rejected["out_of_order"] == 2
    assert [i.kind for i in results.items] == ["put", "delete"]
    send(tracker, "hri/bodies/bob/pose/cam", pose_json("bob", "cam", sec=6))  # really back
    results.wait_for(lambda i: i.kind == "put" and i.value["stamp"]["sec"] == 6)
