"""Our JSON keys on the wire: results go out only while someone subscribes to them
(zenoh's matching status), every other kind always; queries answer either way; a
subscriber that appears gets every current result at once."""

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
    # no pose after it subscribes: the service, told of the subscriber, says ann's result
    (said,) = results.wait_for(lambda i: i.kind == "put", timeout=5)
    assert said.value["body_id"] == "ann" and said.value["stamp"]["sec"] == 10
    send(tracker, "hri/bodies/ann/pose/cam", pose_json("ann", "cam", sec=11))
    results.wait_for(lambda i: i.kind == "put" and i.value["stamp"]["sec"] == 11, timeout=5)
    assert counters_now(service)["results_published"] == 2


def counters_now(service) -> dict[str, int]:
    return service.status().counters
