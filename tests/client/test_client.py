"""FacingClient against a real service over zenoh: cache, transitions, queries."""

from __future__ import annotations

import threading
import time

import pytest

from facing_service import FacingClient, FacingState
from facing_service.testing import loopback_config

from loopback import send, send_delete, wait_until, wait_until_answered
from poses import pose_json

KEY = "hri/bodies/{}/pose/cam"


class Events:
    def __init__(self) -> None:
        self.items: list[tuple] = []
        self.cond = threading.Condition()

    def __call__(self, name: str):
        def record(*args) -> None:
            first = args[0]
            value = (
                (name, first.body_id, first.facing)
                if isinstance(first, FacingState)
                else (name, first.body_id)  # on_lost: a BodyRef
            )
            with self.cond:
                self.items.append(value)
                self.cond.notify_all()

        return record

    def wait_for(self, count: int, timeout: float = 5.0) -> list[tuple]:
        deadline = time.monotonic() + timeout
        with self.cond:
            while len(self.items) < count:
                left = deadline - time.monotonic()
                assert left > 0, f"got {self.items}"
                self.cond.wait(left)
            return list(self.items)


@pytest.fixture
def deployment(net):
    _, ep = net.service()
    tracker = net.client(ep)
    wait_until_answered(tracker, "hri/facing/cam")
    return ep, tracker


def client_for(ep: str) -> FacingClient:
    return FacingClient(session_config=loopback_config(connect=[ep]))


def test_the_cache_is_seeded_at_start_and_kept_live(deployment):
    ep, tracker = deployment
    send(tracker, KEY.format("a"), pose_json("a", "cam", off_deg=5.0, sec=1))
    send(tracker, KEY.format("b"), pose_json("b", "cam", off_deg=90.0, sec=1))
    wait_until_answered(tracker, "hri/facing/cam")
    time.sleep(0.2)
    with client_for(ep) as client:
        assert set(client.bodies("cam")) == {"a", "b"}  # seeded by the query at start
        assert client.bodies_facing("cam") == ["a"]
        assert client.bodies("cam")["b"].angle_deg == pytest.approx(90.0)
        send(tracker, KEY.format("b"), pose_json("b", "cam", off_deg=3.0, sec=2))
        deadline = time.monotonic() + 5
        while client.bodies_facing("cam") != ["a", "b"]:
            assert time.monotonic() < deadline
            time.sleep(0.02)
        assert client.bodies("other") == {}


def test_callbacks_fire_on_transitions_only(deployment):
    ep, tracker = deployment
    events = Events()
    with client_for(ep) as client:
        client.on_facing(events("facing"))
        client.on_not_facing(events("not_facing"))
        client.on_lost(events("lost"))
        changes: list[FacingState] = []
        client.on_change(changes.append)
        offs = [60.0, 5.0, 6.0, 7.0, 40.0, 41.0, 2.0]  # away, toward x3, away x2, toward
        for sec, off in enumerate(offs, start=1):
            send(tracker, KEY.format("a"), pose_json("a", "cam", off_deg=off, sec=sec))
        send_delete(tracker, KEY.format("a"))
        seen = events.wait_for(4)
        assert seen == [
            ("facing", "a", True),
            ("not_facing", "a", False),
            ("facing", "a", True),
            ("lost", "a"),
        ]
        assert len(changes) == len(offs)  # on_change: every result
        assert client.bodies("cam") == {}


def test_registering_on_facing_reports_who_already_faces(deployment):
    ep, tracker = deployment
    send(tracker, KEY.format("a"), pose_json("a", "cam", sec=1))
    wait_until_answered(tracker, "hri/facing/cam")
    time.sleep(0.2)
    events = Events()
    with client_for(ep) as client:
        client.on_facing(events("facing"))
        assert events.wait_for(1) == [("facing", "a", True)]


def test_query_goes_to_the_service_with_another_cone(deployment):
    ep, tracker = deployment
    send(tracker, KEY.format("a"), pose_json("a", "cam", off_deg=30.0, sec=1))
    wait_until_answered(tracker, "hri/facing/cam")
    with client_for(ep) as client:
        (state,) = client.query("cam")
        assert state.body_id == "a" and not state.facing
        (wider,) = client.query("cam", threshold_deg=35)
        assert wider.facing and wider.threshold_deg == 35.0
        with pytest.raises(ValueError, match="threshold_deg"):
            client.query("cam", threshold_deg=500)


def test_a_slow_callback_does_not_stall_the_cache(deployment):
    ep, tracker = deployment
    release = threading.Event()
    with client_for(ep) as client:
        client.on_change(lambda state: release.wait(10))
        for sec in range(1, 50):
            send(tracker, KEY.format("a"), pose_json("a", "cam", sec=sec))
        deadline = time.monotonic() + 5
        while "a" not in client.bodies("cam") or client.bodies("cam")["a"].stamp.sec != 49:
            assert time.monotonic() < deadline, "the cache stalled behind a callback"
            time.sleep(0.02)
        release.set()


def test_query_tells_nobody_there_from_a_wrong_frame_and_a_closed_client(net):
    """Issue 46: `query("base_lnk")` returned [] like an empty room. A frame the service
    does not know raises UnknownFrame naming the frames tracked; a known frame with
    nobody in it is []; a client not open says so by name (it was a bare assert)."""
    from facing_service import ClientNotOpen, FacingError, UnknownFrame

    _, ep = net.service(base_frame="*")
    tracker = net.client(ep)
    wait_until_answered(tracker, "hri/services/facing/*/status")
    send(tracker, KEY.format("a"), pose_json("a", "cam", sec=1))
    with client_for(ep) as client:
        wait_until(lambda: client.query("cam"), 5, "a's result")
        with pytest.raises(UnknownFrame, match="frames tracked: cam") as refused:
            client.query("cma")
        assert isinstance(refused.value, FacingError) and refused.value.reason == "unknown_frame"
        send_delete(tracker, KEY.format("a"))
        wait_until(lambda: client.query("cam") == [], 5, "nobody in cam")
    with pytest.raises(ClientNotOpen):
        client.query("cam")
