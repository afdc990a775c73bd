"""Our JSON keys on the wire: results go out only while someone subscribes to them
(zenoh's matching status), every other kind always; queries answer either way."""

from __future__ import annotations

from loopback import get, send, wait_until, wait_until_answered
from poses import pose_json


def test_results_nobody_subscribes_to_are_neither_formatted_nor_sent(net):
    service, ep = net.service()
    tracker = net.client(ep)
    wait_until_answered(tracker, "hri/facing/cam")
    for sec in range(1, 11):
        send(tracker, "hri/bodies/ann/pose/cam", pose_json("ann", "cam", sec=sec))
    wait_until(lambda: counters_now(service)["samples_accepted"] == 10, 5, "10 poses")
    counters = counters_now(service)
    assert counters["results_published"] == 0  # nobody listens to results
    assert counters["frames_published"] >= 1  # an aggregate is a state change: always sent
    ((_, state),) = get(tracker, "hri/bodies/ann/facing/cam")  # queries answer from state
    assert state["stamp"]["sec"] == 10

    consumer = net.client(ep)
    results = net.recorder(consumer, "hri/bodies/*/facing/cam")
    sec = 10

    def heard() -> bool:  # the matching status reaches the service within a few poses
        nonlocal sec
        sec += 1
        send(tracker, "hri/bodies/ann/pose/cam", pose_json("ann", "cam", sec=sec))
        return bool(results.items)

    wait_until(heard, 5, "results once a consumer subscribes")
    assert results.items[-1].value["body_id"] == "ann"
    assert counters_now(service)["results_published"] >= 1


def counters_now(service) -> dict[str, int]:
    return service.status().counters
