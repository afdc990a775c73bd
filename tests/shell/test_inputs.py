"""The JSON input: what it reads from a sample, what it refuses and says, and the pose
keys it declares for the bodies it reads (from a body's first pose until it is lost)."""

from __future__ import annotations

import logging
import time

import zenoh

from facing_service.client.health import summary
from facing_service.contract.keys import BodyRef
from facing_service.core.records import PoseSample
from facing_service.shell.inputs import JsonInput
from facing_service.shell.ledger import Ledger

from loopback import send, send_delete, wait_until
from poses import pose_json
from service_rig import body_key, pose_key


def is_put(key):
    return lambda item: item.key == key and item.kind == "put"


def test_mistyped_pose_keys_are_counted_and_logged_not_lost_in_silence(rig, caplog):
    """A defect found: a tracker's poses on a mistyped key reached no subscription of the
    service, and nothing said so; they are now refused as invalid keys, counted in the
    status and named in the rejections' log line, and good poses still all come through."""
    service, client, rec = rig()
    caplog.set_level(logging.WARNING, logger="facing_service")
    mistyped = [
        "hri/body/alice/pose/cam",  # body for bodies
        "hri/bodies/alice/pose",  # no frame
        "hri/bodies/alice/pose/cam/x",  # a chunk after the frame
        "hri/bodies/alice/poses/cam",  # poses for pose
        "bodies/alice/pose/cam",  # the namespace left out
    ]
    for sec in (1, 2):
        for key in mistyped:
            send(client, key, pose_json("alice", "cam", sec=sec))
        send(client, pose_key("a"), pose_json("a", "cam", sec=sec))
    results = rec.wait_for(is_put(body_key("a")), count=2)
    assert [r.value["stamp"]["sec"] for r in results] == [1, 2]
    wait_until(
        lambda: service.status().rejected.get("invalid_key") == 2 * len(mistyped),
        5.0,
        "every mistyped pose counted",
    )
    service.close()  # the rejections' summary is said at the latest when it stops
    said = [r.getMessage() for r in caplog.records]
    for key in mistyped:  # each named once, in a line of its own
        assert sum(f"poses on {key} are refused" in line for line in said) == 1, said
    assert any("invalid_key=10" in line for line in said)  # and in the summary


def test_poses_in_another_frame_than_a_fixed_base_frame_are_counted_and_said(net, caplog):
    """A defect found: ``run --base-frame base_lnk`` with poses in base_link: nothing printed,
    nothing logged, 0 accepted and every rejection counter 0. Now each is refused as
    other_frame, the frames are said once, and health's line says it; the watch ends at
    the first pose in the frame read."""
    caplog.set_level(logging.WARNING, logger="facing_service")
    service, ep = net.service(base_frame="base_lnk")
    tracker = net.client(ep)
    wait_until(lambda: service.status().status == "ok", 5.0, "the service up")
    time.sleep(0.3)  # the tracker's session meets the service's
    for sec in (1, 2, 3):
        send(tracker, "hri/bodies/a/pose/base_link", pose_json("a", "base_link", sec=sec))
    wait_until(lambda: service.status().rejected["other_frame"] == 3, 5.0, "3 refused")
    said = [r.getMessage() for r in caplog.records if "the only frame" in r.getMessage()]
    assert said == [
        "poses arrive in frame 'base_link', none yet in 'base_lnk', the only frame this service "
        "reads (--base-frame, FACING_BASE_FRAME): is it misspelt? Refused, counted as "
        "other_frame until a pose in 'base_lnk' arrives"
    ]
    line = summary(service.status(), "at here")
    assert "3 samples refused (3 in another frame than the service's --base-frame" in line
    send(tracker, "hri/bodies/a/pose/base_lnk", pose_json("a", "base_lnk", sec=4))
    wait_until(lambda: service.status().counters["samples_accepted"] == 1, 5.0, "accepted")
    send(tracker, "hri/bodies/b/pose/base_link", pose_json("b", "base_link", sec=5))
    send(tracker, "hri/bodies/a/pose/base_lnk", pose_json("a", "base_lnk", sec=6))
    wait_until(lambda: service.status().counters["samples_accepted"] == 2, 5.0, "accepted")
    assert service.status().rejected["other_frame"] == 3  # no watch once poses flow


def test_a_service_of_every_frame_refuses_no_frame(rig):
    service, client, rec = rig(base_frame="*")
    send(client, "hri/bodies/a/pose/base_link", pose_json("a", "base_link", sec=1))
    rec.wait_for(is_put("hri/bodies/a/facing/base_link"))
    assert service.status().rejected["other_frame"] == 0


def test_a_pose_key_is_declared_from_the_first_pose_until_the_body_is_lost(net):
    _, ep = net.service()
    session = net.client(ep)  # the tracker too: its own puts reach its own subscriber
    ledger = Ledger(time.monotonic)
    source = JsonInput("hri", "cam", 65536, 100, ledger)
    samples = session.declare_subscriber(source.hot_key(), zenoh.handlers.FifoChannel(16))
    try:
        assert source.open(session, lambda item: None) == "hri/bodies/*/pose/cam"
        send(session, pose_key("a"), pose_json("a", "cam"))
        send_delete(session, pose_key("a"))
        poses: list[PoseSample] = []
        assert source.read(next_sample(samples), poses) is None and poses[0].body_id == "a"
        assert source.declared_keys is not None
        assert list(source.declared_keys.exprs) == [pose_key("a")]
        loss = source.read(next_sample(samples), poses)  # the DELETE: a loss for the worker
        assert loss is not None and loss.bodies == [BodyRef(frame_id="cam", body_id="a")]
        source.forget(loss.bodies)
        assert source.declared_keys.exprs == {}
    finally:
        samples.undeclare()
        source.close()


def next_sample(samples: zenoh.Subscriber) -> zenoh.Sample:
    """The next sample, within 5 s (``recv`` would wait for ever)."""
    deadline = time.monotonic() + 5
    while (sample := samples.try_recv()) is None:
        assert time.monotonic() < deadline, "no sample within 5 s"
        time.sleep(0.01)
    return sample
