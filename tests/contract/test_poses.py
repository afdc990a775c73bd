"""Decoding a pose: every rejection reason, the accepted edge cases, and the fast path
that never accepts what the model would not."""

from __future__ import annotations

import contextlib
import json
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from facing_service.contract.poses import (
    Pose,
    Rejected,
    Rejection,
    _decode_with_model,
    _plainly_valid,
    decode_pose,
)
from facing_service.contract.stamps import Time

from poses import pose_dict


def encode(d) -> bytes:
    return json.dumps(d).encode()


def good(**kw):
    return pose_dict("a", "cam", **kw)


def reason_of(payload: bytes, body="a", frame="cam", limit=65536) -> Rejection | None:
    result = decode_pose(payload, body, frame, limit)
    if isinstance(result, Rejected):
        assert result.detail  # every rejection explains itself
        return result.reason
    return None


def with_(d, path, value):
    node = d
    for part in path[:-1]:
        node = node[part]
    if value is ...:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return d


def test_valid_pose_is_decoded():
    result = decode_pose(encode(good(x=2.0, y=1.0, yaw_deg=90.0, sec=7, nanosec=5)), "a", "cam")
    assert isinstance(result, Pose)
    assert result.stamp == Time.of(7, 5)
    assert result.translation == (2.0, 1.0, 0.0)
    assert result.rotation == pytest.approx((0.0, 0.0, math.sqrt(0.5), math.sqrt(0.5)))


def test_quaternion_within_tf2_tolerance_is_normalized():
    d = with_(good(yaw_deg=0.0), ["transform", "rotation", "w"], 1.004)  # |q|^2 = 1.008
    result = decode_pose(encode(d), "a", "cam")
    assert isinstance(result, Pose)
    assert result.rotation == pytest.approx((0.0, 0.0, 0.0, 1.0))


@pytest.mark.parametrize("child", ["", "body_a"])
def test_child_frame_may_be_empty_or_the_body(child):
    assert reason_of(encode(with_(good(), ["child_frame_id"], child))) is None


def test_child_frame_may_be_absent():
    assert reason_of(encode(with_(good(), ["child_frame_id"], ...))) is None


def test_unknown_extra_fields_are_ignored():
    """Bridges that forward full ROS messages may add fields; they do not matter here."""
    assert reason_of(encode({**good(), "extra": {"anything": [1, 2]}})) is None


def test_integer_coordinates_are_accepted():
    d = with_(good(), ["transform", "translation", "x"], 3)
    assert reason_of(encode(d)) is None


CASES = {
    Rejection.PAYLOAD_TOO_LARGE: [encode({**good(), "pad": "x" * 70_000})],
    Rejection.MALFORMED_JSON: [
        b"",
        b"not json",
        b'{"header": ',
        b"\xff\xfe\x00garbage",
        b"[" * 10_000 + b"]" * 10_000,
        encode(good())[:-5],
    ],
    Rejection.SCHEMA: [
        b"[]",
        b"42",
        b"null",
        encode(with_(good(), ["header"], ...)),
        encode(with_(good(), ["transform", "rotation", "w"], ...)),
        encode(with_(good(), ["transform", "translation", "x"], "1.0")),
        encode(with_(good(), ["transform", "translation", "x"], True)),
        encode(with_(good(), ["transform", "translation", "x"], 1e10)),
        encode(with_(good(), ["header", "stamp", "sec"], -1)),
        encode(with_(good(), ["header", "stamp", "sec"], 1.5)),
        encode(with_(good(), ["header", "stamp", "sec"], 2**63)),
        encode(with_(good(), ["header", "stamp", "nanosec"], 1_000_000_000)),
        encode(with_(good(), ["header", "frame_id"], 5)),
        encode(with_(good(), ["transform"], [1, 2, 3])),
    ],
    Rejection.NON_FINITE: [
        encode(good()).replace(b'"x": 2.0', b'"x": NaN'),
        encode(good()).replace(b'"x": 2.0', b'"x": Infinity'),
        encode(good()).replace(b'"x": 2.0', b'"x": -Infinity'),
        encode(good()).replace(b'"x": 2.0', b'"x": 1e400'),
    ],
    Rejection.FRAME_MISMATCH: [encode(pose_dict("a", "base_link"))],
    Rejection.CHILD_FRAME_MISMATCH: [
        encode(with_(good(), ["child_frame_id"], "body_b")),
        encode(with_(good(), ["child_frame_id"], "a")),
    ],
    Rejection.QUATERNION_NOT_NORMALIZED: [
        encode(with_(good(yaw_deg=0.0), ["transform", "rotation", "w"], 1.006)),
        encode(with_(good(yaw_deg=0.0), ["transform", "rotation", "w"], 0.0)),
        encode(with_(good(yaw_deg=0.0), ["transform", "rotation", "w"], 2.0)),
    ],
}


@pytest.mark.parametrize(
    ("reason", "payload"),
    [(reason, p) for reason, payloads in CASES.items() for p in payloads],
    ids=lambda v: v.value if isinstance(v, Rejection) else None,
)
def test_rejection_reasons(reason, payload):
    assert reason_of(payload) is reason


def test_every_decoder_reason_is_exercised():
    """Reasons not produced by the decoder come from the key parser, the tracker, the
    worker (internal_error: test_service_faults.py), the JSON input (other_frame:
    test_inputs.py) and the ROS 2 input (each exercised in test_ros2_input.py)."""
    ros2 = {r for r in Rejection if r.value.startswith("tf_")} | {
        Rejection.TYPE_MISMATCH,
        Rejection.MALFORMED_CDR,
        Rejection.INVALID_ID,
    }
    decoder_reasons = (
        set(Rejection)
        - ros2
        - {
            Rejection.INVALID_KEY,
            Rejection.OTHER_FRAME,
            Rejection.OUT_OF_ORDER,
            Rejection.CAPACITY,
            Rejection.INTERNAL_ERROR,
        }
    )
    assert decoder_reasons == set(CASES)


def test_payload_limit_is_configurable():
    payload = encode(good())
    assert reason_of(payload, limit=len(payload)) is None
    assert reason_of(payload, limit=len(payload) - 1) is Rejection.PAYLOAD_TOO_LARGE


# -- the fast decoding path: never accepts what the model would not, never differently --

leaf_values = (
    st.integers(-(2**64), 2**64)
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.floats(-3.0, 3.0)
    | st.booleans()
    | st.none()
    | st.text(max_size=5)
    | st.sampled_from(["cam", "body_a", "", "body_b", 1.0, 0, 2**31, 999_999_999, 1e9, -1e9])
    | st.lists(st.integers(), max_size=2)
    | st.dictionaries(st.text(max_size=3), st.integers(), max_size=2)
)
LEAVES = [
    ["header", "stamp", "sec"],
    ["header", "stamp", "nanosec"],
    ["header", "stamp"],
    ["header", "frame_id"],
    ["header"],
    ["child_frame_id"],
    ["transform"],
    ["transform", "translation"],
    ["transform", "rotation"],
    *(["transform", "translation", c] for c in "xyz"),
    *(["transform", "rotation", c] for c in "xyzw"),
]


@settings(max_examples=1500)
@given(
    st.lists(
        st.tuples(st.sampled_from(LEAVES), leaf_values | st.just(...)), min_size=0, max_size=4
    ),
    st.floats(-180, 180),
)
def test_fast_path_accepts_only_what_the_model_accepts_and_decodes_it_identically(edits, yaw):
    d = good(yaw_deg=yaw)
    for path, value in edits:
        # an earlier edit may have replaced a parent: this edit then has nowhere to go
        with contextlib.suppress(KeyError, TypeError):
            with_(d, path, value)
    payload = encode(d)
    fast = _plainly_valid(payload, "a", "cam")
    model = _decode_with_model(payload, "a", "cam")
    if fast is not None:
        assert model == fast
        assert [type(v) for v in (*fast.translation, *fast.rotation)] == [float] * 7
    assert decode_pose(payload, "a", "cam") == (fast if fast is not None else model)


@pytest.mark.parametrize(
    "d",
    [
        good(),
        good(x=3, y=-1, sec=2**31 - 1, nanosec=999_999_999),
        with_(good(), ["child_frame_id"], ...),
        with_(good(), ["child_frame_id"], ""),
        {**good(), "extra": {"anything": [1, 2]}},
        with_(good(yaw_deg=0.0), ["transform", "rotation", "w"], 1.004),
    ],
)
def test_fast_path_takes_the_common_valid_payloads(d):
    """Otherwise the fast path would silently never run and the model pay for every pose."""
    assert _plainly_valid(encode(d), "a", "cam") == _decode_with_model(encode(d), "a", "cam")
    assert isinstance(_plainly_valid(encode(d), "a", "cam"), Pose)


CHILD = '"child_frame_id": "body_a"'


@pytest.mark.parametrize(
    "edit",
    [
        # a key given twice: both parsers keep the last
        lambda p: p.replace(CHILD, '"child_frame_id": "x", ' + CHILD),
        lambda p: p.replace(CHILD, CHILD + ', "child_frame_id": "x"'),
        lambda p: p.replace('"x": 1.5', '"x": 15E-1'),  # exponents
        lambda p: p.replace('"sec": 12', '"sec": 12.0'),  # a float where an int belongs
        lambda p: p.replace('"sec": 12', '"sec": true'),
        lambda p: p.replace('"x": 1.5', '"x": NaN'),
        lambda p: p.replace('"x": 1.5', '"x": 1e400'),
        lambda p: p.replace('"sec": 12', '"sec": 99999999999999999999999'),
        lambda p: p.replace('"frame_id": "cam"', '"frame_id": "\xe3am"'),  # not UTF-8, below
    ],
)
def test_fast_path_and_model_agree_on_json_corners(edit):
    """msgspec's parser and pydantic's differ in places the hypothesis test above does not
    reach (duplicate keys, number forms): where the fast path accepts, the model decodes
    the same; elsewhere the model says why."""
    payload = edit(encode(good(x=1.5, sec=12)).decode()).encode("latin-1")
    assert payload != encode(good(x=1.5, sec=12))  # the edit applied
    fast = _plainly_valid(payload, "a", "cam")
    assert fast is None or fast == _decode_with_model(payload, "a", "cam")
    assert decode_pose(payload, "a", "cam") == _decode_with_model(payload, "a", "cam")
