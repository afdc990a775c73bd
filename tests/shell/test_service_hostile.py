"""Hostile input: fuzzing the decoder, and garbage interleaved with good poses over zenoh."""

from __future__ import annotations

import json
import math
import random
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from facing_service.contract.poses import Pose, Rejected, Rejection, decode_pose
from facing_service.core.detector import classify

from loopback import send, wait_until_answered
from poses import pose_dict, pose_json

VALID = pose_json("a", "cam", x=1.0, y=-0.5, off_deg=7.0, sec=3, nanosec=9)


def check(payload: bytes) -> None:
    """The decoder's contract: never raises; a Pose is sane; a refusal has a known reason."""
    result = decode_pose(payload, "a", "cam", 4096)
    if isinstance(result, Rejected):
        assert isinstance(result.reason, Rejection) and result.detail
        return
    assert isinstance(result, Pose)
    assert all(math.isfinite(v) for v in (*result.translation, *result.rotation))
    assert math.isclose(sum(v * v for v in result.rotation), 1.0, abs_tol=1e-9)
    assert 0 <= result.stamp.nanosec < 1_000_000_000


json_values = st.recursive(
    st.none()
    | st.booleans()
    | st.integers(min_value=-(10**400), max_value=10**400)
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.text(max_size=20),
    lambda inner: (
        st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4)
    ),
    max_leaves=30,
)

# every path to a leaf of a valid pose, to put a hostile value there
LEAVES = [
    ("header", "stamp", "sec"),
    ("header", "stamp", "nanosec"),
    ("header", "frame_id"),
    ("child_frame_id",),
    ("transform", "translation", "x"),
    ("transform", "translation", "z"),
    ("transform", "rotation", "x"),
    ("transform", "rotation", "w"),
    ("header",),
    ("transform",),
]


@settings(max_examples=400, suppress_health_check=[HealthCheck.too_slow])
@given(st.binary(max_size=600))
def test_random_bytes(payload):
    check(payload)


@settings(max_examples=400)
@given(st.data())
def test_mutated_valid_payloads(data):
    payload = bytearray(VALID)
    for _ in range(data.draw(st.integers(1, 6))):
        op = data.draw(st.sampled_from(["flip", "cut", "insert", "delete"]))
        at = data.draw(st.integers(0, max(0, len(payload) - 1)))
        if op == "flip" and payload:
            payload[at] ^= 1 << data.draw(st.integers(0, 7))
        elif op == "cut":
            del payload[at:]
        elif op == "insert":
            payload[at:at] = data.draw(st.binary(min_size=1, max_size=8))
        elif payload:
            del payload[at]
    check(bytes(payload))


@settings(max_examples=400)
@given(st.sampled_from(LEAVES), json_values)
def test_hostile_values_in_a_valid_shape(path, value):
    d = pose_dict("a", "cam")
    node = d
    for part in path[:-1]:
        node = node[part]
    node[path[-1]] = value
    check(json.dumps(d).encode())  # json.dumps writes NaN/Infinity tokens for non-finite


@settings(max_examples=200)
@given(json_values)
def test_arbitrary_json(value):
    check(json.dumps(value).encode())


@pytest.mark.parametrize(
    "payload",
    [
        b"[" * 100_000,
        b'{"a":' * 50_000,
        '{"header": "\u202e\ud7ff\U0001f600"}'.encode(),
        json.dumps(pose_dict("a", "cam")).replace('"cam"', '"c\\u0000am"').encode(),
        json.dumps(pose_dict("a", "cam")).replace("2.0", "1" * 5000).encode(),
        json.dumps(pose_dict("a", "cam")).replace("2.0", "1e-400").encode(),
        b"\xef\xbb\xbf" + VALID,  # a byte-order mark
        VALID + b"trailing",
        VALID.replace(b'"sec": 3', b'"sec": 3, "sec": 4'),  # duplicate key
    ],
    ids=[
        "deep-array",
        "deep-object",
        "unicode",
        "nul",
        "long-number",
        "underflow",
        "bom",
        "trailing",
        "duplicate-key",
    ],
)
def test_pathological_payloads(payload):
    check(payload)


def garbage(rng: random.Random, body: str) -> tuple[str, bytes]:
    """One of many kinds of bad sample for ``body`` (which already has an accepted pose)."""
    key = f"hri/bodies/{body}/pose/cam"
    kind = rng.randrange(9)
    if kind == 0:
        return key, rng.randbytes(rng.randrange(1, 200))
    if kind == 1:
        return key, VALID[: rng.randrange(len(VALID))]
    if kind == 2:
        return key, json.dumps({"header": rng.random()}).encode()
    if kind == 3:
        return key, pose_json(body, "cam").replace(b'"x": 2.0', b'"x": NaN')
    if kind == 4:
        return key, pose_json(body, "map")  # frame mismatch
    if kind == 5:
        return key, pose_json("intruder", "cam")  # child frame mismatch
    if kind == 6:
        return f"hri/bodies/{'x' * 70}/pose/cam", pose_json(body, "cam")  # invalid key
    if kind == 7:
        return key, b"{" + b" " * 70_000 + b"}"  # too large
    return key, pose_json(body, "cam", sec=0)  # older than its accepted pose: out of order


def test_garbage_interleaved_with_valid_poses_over_zenoh(net):
    rng = random.Random(155)
    service, ep = net.service(hysteresis_deg=0.0)
    tracker, consumer = net.client(ep), net.client(ep)
    results = net.recorder(consumer, "hri/bodies/*/facing/cam")
    wait_until_answered(consumer, "hri/facing/cam")

    valid: dict[str, list[dict]] = {f"b{b}": [] for b in range(5)}
    n_garbage, sent_garbage = 10_000, 0
    for i in range(500):
        body = f"b{i % 5}"
        pose = pose_dict(
            body,
            "cam",
            x=rng.uniform(0.5, 5),
            y=rng.uniform(-3, 3),
            off_deg=rng.uniform(-60, 60),
            sec=i + 1,
        )
        valid[body].append(pose)
        send(tracker, f"hri/bodies/{body}/pose/cam", json.dumps(pose).encode())
        for _ in range(20):
            send(tracker, *garbage(rng, body))
            sent_garbage += 1
    assert sent_garbage == n_garbage

    for body, poses in valid.items():
        received = results.wait_for(
            lambda item, k=body: item.key.split("/")[2] == k, count=len(poses), timeout=30
        )
        t = np.array([[p["transform"]["translation"][c] for c in "xyz"] for p in poses])
        q = np.array([[p["transform"]["rotation"][c] for c in "xyzw"] for p in poses])
        expected = classify(t, q, 20.0)
        assert [r.value["stamp"]["sec"] for r in received] == [
            p["header"]["stamp"]["sec"] for p in poses
        ]
        assert [r.value["facing"] for r in received] == expected.facing.tolist()
        np.testing.assert_allclose(
            [r.value["angle_deg"] for r in received], expected.angle_deg, atol=1e-9
        )

    # The garbage came from the tracker's session, a query from another session may
    # overtake its last samples: wait (bounded) until the service has handled them all.
    deadline = time.monotonic() + 30
    while (status := service.status()).inbox_depth or sum(status.rejected.values()) < n_garbage:
        assert time.monotonic() < deadline, status
        time.sleep(0.05)
    assert status.status == "ok"
    assert sum(status.rejected.values()) == n_garbage
    assert status.counters["samples_accepted"] == 500
    assert len(results.items) == 500  # garbage never produced a result
