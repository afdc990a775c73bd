"""Faults: a router that crashes and comes back, a restarted service, SIGTERM in a flood."""

from __future__ import annotations

import signal
import threading
import time

import pytest

from facing_service.testing import LOOPBACK_FLAGS, running_cli

from loopback import endpoint, free_port, get, send, wait_until, wait_until_answered
from network import wait_until_heard
from poses import pose_json

pytestmark = pytest.mark.slow  # processes, recordings or seconds-long scenarios

FRAME_KEY = "hri/facing/cam"


def resume_time(tracker, recorder, first_sec: int, timeout: float = 30.0) -> float:
    """Send a new pose every 50 ms until its result comes back; seconds it took."""
    started = time.monotonic()
    sec = first_sec
    while time.monotonic() - started < timeout:
        send(tracker, "hri/bodies/a/pose/cam", pose_json("a", "cam", sec=sec))
        time.sleep(0.05)
        if any(i.value["stamp"]["sec"] >= first_sec for i in recorder.items if i.kind == "put"):
            return time.monotonic() - started
        sec += 1
    raise AssertionError(f"no result for a new pose within {timeout} s")


def test_service_in_client_mode_resumes_after_the_router_restarts(net):
    router = net.router()
    ep = endpoint(router.port)
    service, _ = net.service(mode="client", connect=[ep], listen=[])
    tracker = net.client(ep, mode="client")
    consumer = net.client(ep, mode="client")
    results = net.recorder(consumer, "hri/bodies/*/facing/cam")
    wait_until_answered(consumer, FRAME_KEY)
    send(tracker, "hri/bodies/a/pose/cam", pose_json("a", "cam", sec=1))
    results.wait_for(lambda i: i.kind == "put")

    router.kill()  # a crash, not a clean stop
    time.sleep(0.5)
    router.start()  # same port
    took = resume_time(tracker, results, first_sec=100)
    print(f"\nrouter restart: results for new poses resumed {took:.2f} s after the restart")
    assert service.status().status == "ok"
    assert dict(get(consumer, "hri/bodies/*/facing/cam"))  # and queries are answered again


def test_a_restarted_service_rebuilds_its_state_from_incoming_samples(net):
    port = free_port()
    first, _ = net.service(listen=[endpoint(port)])
    tracker = net.client(endpoint(port))
    wait_until_answered(tracker, FRAME_KEY)
    send(tracker, "hri/bodies/a/pose/cam", pose_json("a", "cam", sec=1))
    send(tracker, "hri/bodies/b/pose/cam", pose_json("b", "cam", sec=1, off_deg=90))
    first.close()

    net.service(listen=[endpoint(port)])  # same endpoint, fresh state
    wait_until_answered(tracker, FRAME_KEY, timeout=20)  # the tracker peer reconnects
    assert get(tracker, FRAME_KEY)[0][1]["bodies_tracked"] == []
    for sec in (2, 3):
        send(tracker, "hri/bodies/a/pose/cam", pose_json("a", "cam", sec=sec))
        send(tracker, "hri/bodies/b/pose/cam", pose_json("b", "cam", sec=sec, off_deg=90))
    deadline = time.monotonic() + 10
    while get(tracker, FRAME_KEY)[0][1]["bodies_tracked"] != ["a", "b"]:
        assert time.monotonic() < deadline
        time.sleep(0.05)
    assert get(tracker, FRAME_KEY)[0][1]["bodies_facing"] == ["a"]


def test_sigterm_during_a_flood_exits_cleanly_within_two_seconds(net):
    port = free_port()
    flags = ("-l", endpoint(port), "--base-frame", "cam", *LOOPBACK_FLAGS)
    with running_cli("run", *flags) as proc:
        tracker = net.client(endpoint(port))
        wait_until_answered(tracker, FRAME_KEY)
        stop = threading.Event()
        payloads = [pose_json(f"b{b}", "cam", sec=1) for b in range(100)]

        def flood() -> None:
            i = 0
            while not stop.is_set():
                send(tracker, f"hri/bodies/b{i % 100}/pose/cam", payloads[i % 100])
                i += 1

        flooder = threading.Thread(target=flood)
        flooder.start()
        try:
            time.sleep(1.5)
            started = time.monotonic()
            proc.send_signal(signal.SIGTERM)
            code = proc.wait(timeout=10)
            elapsed = time.monotonic() - started
        finally:
            stop.set()
            flooder.join(timeout=10)
        output = proc.stdout.read()
    print(f"\nSIGTERM during a flood: exit {code} after {elapsed:.2f} s")
    assert code == 0, output
    # The contract's deadline, not a performance measurement.
    assert elapsed < 2.0, f"took {elapsed:.2f} s; output:\n{output[-2000:]}"
    assert "stopped" in output


def test_a_pose_that_meets_a_bug_is_refused_alone(net, monkeypatch):
    """A bug used to lose the whole batch around it, and leave the tracker half-changed.
    Now the batch is undone and its poses go again one by one: only the one at fault is
    refused (internal_error); the status is degraded until a batch has no error."""
    service, ep = net.service()
    ingest = service._tracker.ingest

    def fails_on_bad(samples, now):
        if any(s.body_id == "bad" for s in samples):
            raise RuntimeError("a bug that one pose meets")
        return ingest(samples, now)

    monkeypatch.setattr(service._tracker, "ingest", fails_on_bad)
    tracker = net.client(ep)
    results = net.recorder(tracker, "hri/bodies/*/facing/cam")
    wait_until_answered(tracker, FRAME_KEY)
    wait_until_heard(service)
    for sec in range(1, 21):
        send(tracker, "hri/bodies/a/pose/cam", pose_json("a", "cam", sec=sec))
        send(tracker, "hri/bodies/bad/pose/cam", pose_json("bad", "cam", sec=sec))
    results.wait_for(lambda i: i.key.startswith("hri/bodies/a/"), count=20)
    status = service.status()
    assert status.rejected["internal_error"] == 20 and status.counters["samples_accepted"] == 20
    assert status.counters["worker_errors"] >= 20
    assert not [i for i in results.items if "/bad/" in i.key]
    send(tracker, "hri/bodies/a/pose/cam", pose_json("a", "cam", sec=21))
    wait_until(lambda: service.status().status == "ok", 5, "ok after a clean batch")


def fast_client(net, ep: str):
    """A tracker or consumer that reconnects as the service does (--reconnect-s 0.25,1):
    zenoh's own 1-4 s would measure the test's sessions, not the service."""
    import zenoh

    from facing_service.tools.loopback import loopback_config

    conf = loopback_config(connect=[ep], mode="client")
    conf.insert_json5("connect/retry", "{period_init_ms: 250, period_max_ms: 1000}")
    session = zenoh.open(conf)
    net._closers.append(session.close)
    return session


def test_a_router_outage_is_said_when_it_starts_and_ends_and_results_resume(
    net, caplog, monkeypatch
):
    """The router killed, back after 3 s (rmw_zenohd restarted). The loss is
    logged and shown in the status (outage_s; "no router" past its bound), the return is
    logged with how long it lasted, and results flow again soon (zenoh's default backoff
    left them stopped 4 s after the router was back; printed, not asserted: no timing
    asserts on a shared machine)."""
    import logging

    from facing_service.shell import service as service_module
    from facing_service.shell.links import PERIOD_S

    caplog.set_level(logging.WARNING, logger="facing_service")
    monkeypatch.setattr(service_module, "NO_ROUTER_AFTER_S", 1.0)
    router = net.router()
    ep = endpoint(router.port)
    service, _ = net.service(mode="client", connect=[ep], listen=[])
    tracker, consumer = fast_client(net, ep), fast_client(net, ep)
    results = net.recorder(consumer, "hri/bodies/*/facing/cam")
    wait_until_answered(consumer, FRAME_KEY)
    send(tracker, "hri/bodies/a/pose/cam", pose_json("a", "cam", sec=1))
    results.wait_for(lambda i: i.kind == "put")
    assert service.status().outage_s is None
    time.sleep(2 * PERIOD_S)  # the watch has seen the link (all above can take 2 ms)

    router.kill()
    lost = time.monotonic()
    wait_until(lambda: "lost every router and peer" in caplog.text, 5, "the loss said")
    said_after = time.monotonic() - lost
    wait_until(lambda: service.status().status == "no router", 5, "the status")
    assert service.status().outage_s > 1.0
    time.sleep(max(0.0, 3.0 - (time.monotonic() - lost)))
    router.start()  # same port
    took = resume_time(tracker, results, first_sec=100)
    wait_until(lambda: "back in touch with" in caplog.text, 5, "the return said")
    print(f"\nrouter outage: loss said after {said_after:.2f} s; results for new poses "
          f"resumed {took:.2f} s after the router was back")  # fmt: skip
    (back,) = [r.getMessage() for r in caplog.records if "back in touch" in r.getMessage()]
    lasted = float(back.split(" after ")[1].split(" s")[0])
    assert ep in back and lasted >= 2.9, back  # the router was away at least 3 s
    status = service.status()
    assert status.status == "ok" and status.outage_s is None


def test_the_ros2_path_recovers_after_the_robots_router_restarts(net, caplog):
    """Rmw_zenohd restarted (killed, back after 3 s). /tf_static comes back from
    the robot's transient-local cache, the tracked lists and /tf stream again, and the
    service answers on the robot's topics: results for poses stamped after the restart."""
    import logging
    import threading as th

    import zenoh

    from facing_service.tools.loopback import loopback_config

    import rmw_zenoh
    from ros_messages import S, ids_list, tf_message, transform, type_of, yaw_q

    caplog.set_level(logging.WARNING, logger="facing_service")
    router = net.router()
    ep = endpoint(router.port)
    net.robot_service(ep, base_frame="base_link")
    conf = loopback_config(connect=[ep], mode="client")
    conf.insert_json5("connect/retry", "{period_init_ms: 250, period_max_ms: 1000}")
    robot_session = zenoh.open(conf)
    net._closers.append(robot_session.close)
    robot = rmw_zenoh.Robot(robot_session, rmw_zenoh.JAZZY_0_2_10)
    consumer = fast_client(net, ep)
    results = net.recorder(consumer, "hri/bodies/body_a/facing/base_link")
    static = transform("base_link", "camera", S, (0.0, 0.0, 1.0), yaw_q(0))
    robot.publish("/tf_static", type_of("/tf_static"), tf_message(static), latched=True)
    stop, clock = th.Event(), [S]

    def stream() -> None:  # the robot's tracker at 30 Hz, outage or not
        while not stop.wait(1 / 30):
            clock[0] += S // 30
            body = transform("camera", "body_a", clock[0], (2.0, 0.0, -1.0), yaw_q(180))
            try:
                robot.publish("/humans/bodies/tracked", type_of("/humans/bodies/tracked"),
                              ids_list(["a"]))  # fmt: skip
                robot.publish("/tf", type_of("/tf"), tf_message(body))
            except zenoh.ZError:
                pass  # no router: rmw_zenoh drops it too

    streaming = th.Thread(target=stream, daemon=True)
    streaming.start()
    try:
        results.wait_for(lambda i: i.kind == "put", timeout=15)
        router.kill()
        time.sleep(3.0)
        router.start()
        back = time.monotonic()
        restarted_at = clock[0]
        wait_until(
            lambda: any(
                i.kind == "put"
                and i.value["stamp"]["sec"] * S + i.value["stamp"]["nanosec"] > restarted_at
                for i in results.items
            ),
            30,
            "a result for a pose stamped after the restart",
        )
        print(f"\nROS 2 path: results again {time.monotonic() - back:.2f} s after the "
              "robot's router was back")  # fmt: skip
    finally:
        stop.set()
        streaming.join(timeout=2)
        robot.close()
    assert "lost every router and peer" in caplog.text
    wait_until(lambda: "back in touch" in caplog.text, 5, "the return said")


def test_a_tracker_that_restarts_and_reuses_its_ids_is_followed(net):
    """A tracker crashes and restarts, its clock starting over: its first poses
    are older than the body's last, refused as late until three in a row (each newer than
    the one before) show a new clock; then the body is lost (DELETE) and followed anew.
    A tracker that stopped cleanly (DELETE) and restarts with newer stamps is back at once."""
    service, ep = net.service()
    consumer = net.client(ep)
    results = net.recorder(consumer, "hri/bodies/a/facing/cam")
    wait_until_answered(consumer, FRAME_KEY)
    wait_until_heard(service)
    first = net.client(ep)
    wait_until_answered(first, FRAME_KEY)
    for sec in (1000, 1001):
        send(first, "hri/bodies/a/pose/cam", pose_json("a", "cam", sec=sec))
    results.wait_for(lambda i: i.kind == "put" and i.value["stamp"]["sec"] == 1001)
    first.close()  # crashed: no DELETE

    again = net.client(ep)  # restarted: its clock from 1 s
    wait_until_answered(again, FRAME_KEY)
    for sec in (1, 2, 3, 4):
        send(again, "hri/bodies/a/pose/cam", pose_json("a", "cam", sec=sec, off_deg=60))
    results.wait_for(lambda i: i.kind == "put" and i.value["stamp"]["sec"] == 4)
    after = [i for i in results.items if i.kind == "delete" or i.value["stamp"]["sec"] < 1000]
    assert [(i.kind, None if i.kind == "delete" else i.value["stamp"]["sec"]) for i in after] == [
        ("delete", None),
        ("put", 3),
        ("put", 4),
    ]  # the two first refused as late; the third shows the new clock
    status = service.status()
    assert status.counters["clock_restarts"] == 1 and status.rejected["out_of_order"] == 2

    again.delete("hri/bodies/a/pose/cam")  # a clean stop
    results.wait_for(lambda i: i.kind == "delete", count=2)
    send(again, "hri/bodies/a/pose/cam", pose_json("a", "cam", sec=5))  # restarted, later
    results.wait_for(lambda i: i.kind == "put" and i.value["stamp"]["sec"] == 5)
    assert service.status().counters["clock_restarts"] == 1


def test_whoever_is_answered_on_results_is_answered_on_the_status(net):
    """Declarations reach a router in order: the status queryable, declared first, is
    there for anyone the results' queryables answer (CI once asked between the two; with
    the status declared last, 6 of 40 service processes under load missed it)."""
    router = net.router()
    ep = endpoint(router.port)
    consumer = net.client(ep, mode="client")
    for i in range(10):
        flags = ("-e", ep, "--base-frame", "cam", "--instance", f"i{i}")
        with running_cli("run", *LOOPBACK_FLAGS, *flags):
            wait_until_answered(consumer, FRAME_KEY, timeout=20)
            replies = consumer.get(f"hri/services/facing/i{i}/status")
            assert [r for r in replies if r.ok is not None], f"service {i}: no status"
