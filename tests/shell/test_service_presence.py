"""Who is there over time, end to end: the sequences a real tracker sends (one person
stopping while another arrives seldom, junk after a stop, a 1 Hz detector), through a
real service over zenoh on loopback. The exact timings are the core's
(tests/core/test_silence.py); here, what a robot developer sees: DELETEs, the status
and the log."""

from __future__ import annotations

import logging
import time

import pytest

from loopback import send, wait_until_answered
from poses import pose_json
from service_rig import FRAME_KEY, body_key, pose_key

pytestmark = pytest.mark.slow


def is_delete(body: str):
    return lambda item: item.key == body_key(body) and item.kind == "delete"


def test_a_person_who_stops_is_lost_while_another_arrives_every_3_s(rig):
    """Before: P was never lost: each 3 s pause of Q read as the input silent, its pose
    as the input back, and the hold moved P's time on by the pause, every time."""
    _service, client, rec = rig()
    send(client, pose_key("Q"), pose_json("Q", "cam", sec=1))
    started, i = time.monotonic(), 0
    while time.monotonic() - started < 1.0:  # P at 30 Hz for 1 s
        i += 1
        send(client, pose_key("P"), pose_json("P", "cam", sec=1, nanosec=i * 1000))
        time.sleep(1 / 30)
    stopped = time.monotonic()
    for k in range(1, 5):  # then Q alone, a pose every 3 s (12 s watched)
        time.sleep(max(0.0, stopped + 3.0 * k - time.monotonic()))
        send(client, pose_key("Q"), pose_json("Q", "cam", sec=1 + k))
    rec.wait_for(is_delete("P"), timeout=1.0)


def test_refused_samples_are_not_the_input_speaking(rig):
    """Before: junk after a stop read as the input back (the log said "the 5 people held
    go on as they were"), and moved the people's time on."""
    service, client, rec = rig()
    for body in "abcde":
        send(client, pose_key(body), pose_json(body, "cam"))
    rec.wait_for(lambda i: i.key == FRAME_KEY and len(i.value["bodies_tracked"]) == 5)
    time.sleep(2.5)  # silent now, and said (its rate unknown yet: after 2 s), people held
    for _ in range(9):
        send(client, pose_key("junk"), b"{not json")
    wait_until_answered(client, FRAME_KEY)  # the worker has read the junk
    status = service.status()
    assert status.rejected["malformed_json"] == 9
    assert status.input.silent and status.input.last_heard_s >= 2.5
    assert status.input.held == 5


def test_a_1_hz_tracker_is_a_rate_not_a_silence(rig, caplog):
    """Before: a WARNING pair (silent, back) every second."""
    caplog.set_level(logging.WARNING, logger="facing_service")
    _service, client, rec = rig()
    for sec in range(1, 9):
        send(client, pose_key("a"), pose_json("a", "cam", sec=sec))
        time.sleep(1.0)
    warnings = [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING]
    assert len(warnings) <= 2, warnings
    assert not [i for i in rec.on(body_key("a")) if i.kind == "delete"]
