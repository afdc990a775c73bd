"""No ghosts: what consumers are told stays true when trackers go silent, deletes race
late poses, or the service itself dies."""

from __future__ import annotations

import contextlib
import json
import random
import statistics
import threading
import time

import pytest
import zenoh

from facing_service import FacingClient
from facing_service.testing import LOOPBACK_FLAGS, loopback_config, running_cli

from loopback import endpoint, get, send, send_delete, wait_until_answered
from memory import rss_mb
from network import wait_until_heard
from poses import pose_json, replay
from proxy import Proxy

pytestmark = pytest.mark.slow  # processes, recordings or seconds-long scenarios


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
    wait_until_heard(service)
    send(tracker, "hri/bodies/bob/pose/cam", pose_json("bob", "cam", sec=5))
    results.wait_for(lambda i: i.kind == "put")
    send_delete(tracker, "hri/bodies/bob/pose/cam")
    send(tracker, "hri/bodies/bob/pose/cam", pose_json("bob", "cam", sec=4))  # late
    send(tracker, "hri/bodies/bob/pose/cam", pose_json("bob", "cam", sec=5))  # repeated
    wait_until_answered(tracker, "hri/facing/cam")  # the worker is past them
    ((kind, error),) = get(tracker, "hri/bodies/bob/facing/cam")  # no result: said so
    assert (kind, error["error"]) == ("error", "empty_frame")  # bob was the only one
    assert service.status().rejected["out_of_order"] == 2
    results.wait_for(lambda i: i.kind == "delete")  # sent by the publisher thread, after
    assert [i.kind for i in results.items] == ["put", "delete"]
    send(tracker, "hri/bodies/bob/pose/cam", pose_json("bob", "cam", sec=6))  # really back
    results.wait_for(lambda i: i.kind == "put" and i.value["stamp"]["sec"] == 6)


# -- consumers follow the service's liveliness ---------------------------------------------


def service_process(ep: str, *flags: str):
    """The real service CLI in client mode of the router at ``ep``."""
    return running_cli(
        "run", "-m", "client", "-e", ep, *LOOPBACK_FLAGS, "--base-frame", "cam", *flags
    )


class Crowd:
    """A tracker streaming ``bodies`` at 30 Hz, facing the robot, from a thread; it carries
    on through a router's absence as a tracker does."""

    def __init__(self, session: zenoh.Session, bodies: list[str]) -> None:
        self.session, self.bodies = session, bodies
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        i = 0
        while not self._stop.wait(1 / 30):
            i += 1
            sec, nanosec = divmod(1_000_000_000 + i * 33_333_333, 1_000_000_000)
            for n, body in enumerate(self.bodies):
                x, y = 1.5 + n % 4, n % 5 - 2.0
                pose = pose_json(body, "cam", x=x, y=y, sec=sec, nanosec=nanosec)
                with contextlib.suppress(zenoh.ZError):
                    send(self.session, f"hri/bodies/{body}/pose/cam", pose)

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
    tracker = Crowd(net.client(ep, mode="client"), ["alice"])
    lost: list[tuple[str, str]] = []
    config = loopback_config(connect=[ep], mode="client")
    try:
        with FacingClient("hri", "cam", session_config=config, timeout_s=0.2) as client:
            client.on_lost(lambda body: lost.append((body.body_id, body.frame_id)))
            with service_process(ep) as proc:
                wait_until(lambda: client.bodies_facing("cam") == ["alice"], timeout=20)
                proc.kill()  # SIGKILL: as an OOM kill or a crash would
                took = wait_until(lambda: client.bodies_facing("cam") == [], timeout=5)
                proc.wait()
            print(f"\nkill -> client reports lost: {took:.3f} s")
            assert took <= 1.0
            # the callback runs on the client's callback thread, after the cache says so
            wait_until(lambda: lost == [("alice", "cam")], timeout=5)
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
    tracker = Crowd(net.client(endpoint(router.port), mode="client"), ["alice"])
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


def test_chaos_kills_and_restarts_leave_no_ghost(net):
    """20 bodies at 30 Hz; the service SIGKILLed and restarted 10 times at random moments,
    the router killed and restarted once. No body is ever reported facing by the client
    while no live service vouches for it, and no result of a dead instance reaches a raw
    subscriber after its token vanished."""
    rng = random.Random(13)
    router = net.router()
    ep = endpoint(router.port)
    crowd = Crowd(net.client(ep, mode="client"), [f"p{b}" for b in range(20)])
    observer = net.client(ep, mode="client")
    lock = threading.Lock()
    gone_at: dict[str, float] = {}  # instance -> when its token vanished
    late: list[str] = []  # results of an instance received after its token vanished

    def on_token(sample: zenoh.Sample) -> None:
        if sample.kind == zenoh.SampleKind.DELETE:
            with lock:
                gone_at[str(sample.key_expr).rsplit("/", 1)[-1]] = time.monotonic()

    def on_result(sample: zenoh.Sample) -> None:
        if sample.kind == zenoh.SampleKind.PUT:
            instance = json.loads(sample.payload.to_bytes())["instance"]
            with lock:
                if instance in gone_at:
                    late.append(instance)

    tokens = observer.liveliness().declare_subscriber("hri/services/facing/*", on_token)
    raw = observer.declare_subscriber("hri/bodies/*/facing/cam", on_result)
    ghosts, checks = 0, 0
    kill_to_lost, restart_to_fresh, service_rss = [], [], []
    config = loopback_config(connect=[ep], mode="client")
    client_rss_start = rss_mb()
    try:
        with FacingClient("hri", "cam", session_config=config, timeout_s=0.2) as client:
            stop_watch = threading.Event()

            def watch() -> None:  # the invariant, checked every 5 ms
                nonlocal ghosts, checks
                while not stop_watch.wait(0.005):
                    with client._lock:  # one consistent view of cache and tokens
                        facing = any(s.facing for s in client._bodies.states.values())
                        live = bool(client._bodies.live)
                    checks += 1
                    ghosts += facing and not live

            watcher = threading.Thread(target=watch, daemon=True)
            watcher.start()
            for cycle in range(10):
                if cycle == 5:  # the router too, once: the service reconnects by itself
                    router.kill()
                    time.sleep(0.3)
                    router.start()
                with service_process(ep) as proc:
                    wait_until(lambda: client.live_instances, timeout=20)
                    up = time.monotonic()
                    wait_until(lambda: len(client.bodies_facing("cam")) == 20, timeout=10)
                    restart_to_fresh.append(time.monotonic() - up)
                    time.sleep(rng.uniform(0.2, 1.5))
                    service_rss.append(rss_mb(proc.pid))
                    proc.kill()
                    killed = time.monotonic()
                    wait_until(lambda: client.bodies("cam") == {}, timeout=5)
                    kill_to_lost.append(time.monotonic() - killed)
                    proc.wait()
            stop_watch.set()
            watcher.join()
            time.sleep(0.3)  # anything late would have arrived by now
    finally:
        crowd.close()
        raw.undeclare()
        tokens.undeclare()
    client_rss_end = rss_mb()
    print(
        f"\nchaos: kill -> client lost: max {max(kill_to_lost):.3f} s, "
        f"median {statistics.median(kill_to_lost):.3f} s; restart -> 20 fresh bodies: "
        f"max {max(restart_to_fresh):.3f} s, median {statistics.median(restart_to_fresh):.3f} s; "
        f"ghosts {ghosts} in {checks} checks; late results from dead instances {len(late)}; "
        f"client process RSS {client_rss_start:.0f} -> {client_rss_end:.0f} MB; "
        f"service RSS {min(service_rss):.0f}-{max(service_rss):.0f} MB"
    )
    assert ghosts == 0 and late == [] and checks > 1000
    assert max(kill_to_lost) <= 1.0
    assert max(restart_to_fresh) <= 1.0
