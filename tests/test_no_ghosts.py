"""No ghosts: what consumers are told stays true when trackers go silent, deletes race
late poses, or the service itself dies."""

from __future__ import annotations

import threading
import time

import zenoh
from test_engagement_service import replay

from facing_service import FacingClient
from facing_service.testing import LOOPBACK_FLAGS, loopback_config, running_cli

from loopback import endpoint, get, send, send_delete, wait_until_answered
from poses import pose_json
from proxy import Proxy


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


# -- consumers follow the service's liveliness ---------------------------------------------


def service_process(ep: str, *flags: str):
    """The real service CLI in client mode of the router at ``ep``."""
    return running_cli(
        "run", "-m", "client", "-e", ep, *LOOPBACK_FLAGS, "--base-frame", "cam", *flags
    )


class Tracker:
    """Streams alice facing the robot at 30 Hz from a thread, stamps always increasing."""

    def __init__(self, session: zenoh.Session) -> None:
        self.session = session
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        i = 0
        while not self._stop.wait(1 / 30):
            i += 1
            sec, nanosec = divmod(1_000_000_000 + i * 33_333_333, 1_000_000_000)
            pose = pose_json("alice", "cam", sec=sec, nanosec=nanosec)
            send(self.session, "hri/bodies/alice/pose/cam", pose)

    def close(self) -> None:
        self._stop.set()
        self._thread.join(timeout=2)


def wait_until(predicate, timeout: float = 10.0) -> float:
    """Seconds it took for ``predicate`` to hold; AssertionError on time-out."""
    started = time.monotonic()
    while not predicate():
        assert time.monotonic() - started < timeout, "timed out"
        time.sleep(0.01)
    return time.monotonic() - started


def test_a_killed_service_leaves_no_ghost_and_a_restarted_one_reseeds(net):
    router = net.router()
    ep = endpoint(router.port)
    tracker = Tracker(net.client(ep, mode="client"))
    lost: list[tuple[str, str]] = []
    config = loopback_config(connect=[ep], mode="client")
    try:
        with FacingClient("hri", "cam", session_config=config, timeout_s=0.2) as client:
            client.on_lost(lambda body, frame: lost.append((body, frame)))
            with service_process(ep) as proc:
                wait_until(lambda: client.bodies_facing("cam") == ["alice"], timeout=20)
                proc.kill()  # SIGKILL: as an OOM kill or a crash would
                took = wait_until(lambda: client.bodies_facing("cam") == [], timeout=5)
                proc.wait()
            print(f"\nkill -> client reports lost: {took:.3f} s")
            assert took <= 1.0 and lost == [("alice", "cam")]
            assert client.live_instances == set()
            with service_process(ep):
                up = wait_until(lambda: client.live_instances, timeout=20)
                fresh = wait_until(lambda: client.bodies_facing("cam") == ["alice"])
                print(f"restart -> first fresh result: {fresh:.3f} s after its token ({up:.1f} s)")
                assert fresh <= 1.0
    finally:
        tracker.close()


def test_a_partitioned_service_is_noticed_within_its_lease(net):
    """The link between the service and its router stops carrying anything, no FIN: the
    router drops the service after the lease the service announces (1 s here, through the
    usual --cfg), and consumers lose what it said."""
    router = net.router()
    proxy = Proxy(router.port)
    tracker = Tracker(net.client(endpoint(router.port), mode="client"))
    config = loopback_config(connect=[endpoint(router.port)], mode="client")
    lease = ("--cfg", "transport/link/tx/lease:1000", "--cfg", "transport/link/tx/keep_alive:4")
    try:
        with (
            FacingClient("hri", "cam", session_config=config, timeout_s=0.2) as client,
            service_process(endpoint(proxy.port), *lease),
        ):
            wait_until(lambda: client.bodies_facing("cam") == ["alice"], timeout=20)
            proxy.cut()
            took = wait_until(lambda: client.bodies_facing("cam") == [], timeout=10)
            print(f"\npartition -> client reports lost: {took:.3f} s (lease 1 s)")
            assert took <= 1.0 + 1.0
    finally:
        tracker.close()
        proxy.close()
