"""Input poses: the ``geometry_msgs/TransformStamped``-shaped payload a tracker sends, the rules
that decode it, and every reason a sample is refused (``Rejection``: stable codes, counted
and reported).

Shaped like ROS 2's message so that a bridge can forward tf messages unchanged. The
models are the authority for every rejection reason and detail; ``decode_pose`` checks
the plainly valid case by hand first (the hot path) and falls back to them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum
from typing import Annotated, Any

import msgspec
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from .stamps import MAX_NANOSEC, MAX_SEC, NS_PER_S, Stamp, Time

#: tf2's tolerance on a quaternion's squared norm before it refuses to normalize it.
QUATERNION_TOLERANCE = 0.01
#: Translations beyond this (metres) are refused: no tracker sees that far, and bounding
#: them keeps ``-R^T t`` far from float overflow, so no inf/NaN can come out of the core.
MAX_TRANSLATION_M = 1e9
DEFAULT_MAX_PAYLOAD_BYTES = 65536
_INPUT = ConfigDict(strict=True, allow_inf_nan=False)
Coordinate = Annotated[float, Field(ge=-MAX_TRANSLATION_M, le=MAX_TRANSLATION_M)]
QuaternionComponent = Annotated[float, Field(ge=-2.0, le=2.0)]


class Header(BaseModel):
    model_config = _INPUT
    stamp: Stamp
    frame_id: str


class Vector3(BaseModel):
    model_config = _INPUT
    x: Coordinate
    y: Coordinate
    z: Coordinate


class Quaternion(BaseModel):
    model_config = _INPUT
    x: QuaternionComponent
    y: QuaternionComponent
    z: QuaternionComponent
    w: QuaternionComponent


class Transform(BaseModel):
    model_config = _INPUT
    translation: Vector3
    rotation: Quaternion


class TransformStamped(BaseModel):
    """Input: the pose of ``body_<id>`` in the base frame ``header.frame_id``."""

    model_config = _INPUT
    header: Header
    child_frame_id: str = ""
    transform: Transform


def pose_dict(
    body_id: str,
    frame_id: str,
    stamp: Time,
    translation: tuple[float, float, float],
    rotation: tuple[float, float, float, float],
) -> dict[str, Any]:
    """The input contract's payload as a tracker publishes it (``TransformStamped``-shaped:
    ``body_<id>`` in ``frame_id``): the one builder the simulator, the benchmarks and the
    tests use."""
    (x, y, z), (qx, qy, qz, qw) = translation, rotation
    return {
        "header": {"stamp": {"sec": stamp.sec, "nanosec": stamp.nanosec}, "frame_id": frame_id},
        "child_frame_id": f"body_{body_id}",
        "transform": {
            "translation": {"x": x, "y": y, "z": z},
            "rotation": {"x": qx, "y": qy, "z": qz, "w": qw},
        },
    }


def yaw_rotation(yaw_deg: float) -> tuple[float, float, float, float]:
    """The unit quaternion of a turn of ``yaw_deg`` about z."""
    half = math.radians(yaw_deg) / 2.0
    return (0.0, 0.0, math.sin(half), math.cos(half))


class Rejection(str, Enum):
    """Why an input sample was refused. Stable codes: they are counted and reported."""

    INVALID_KEY = "invalid_key"
    PAYLOAD_TOO_LARGE = "payload_too_large"
    MALFORMED_JSON = "malformed_json"
    SCHEMA = "schema"
    NON_FINITE = "non_finite"
    FRAME_MISMATCH = "frame_mismatch"
    CHILD_FRAME_MISMATCH = "child_frame_mismatch"
    QUATERNION_NOT_NORMALIZED = "quaternion_not_normalized"
    OTHER_FRAME = "other_frame"  # a pose in another frame than a fixed --base-frame
    OUT_OF_ORDER = "out_of_order"
    CAPACITY = "capacity"
    INTERNAL_ERROR = "internal_error"  # handling it met a bug (counted in worker_errors too)
    # ROS 2 input (--input ros2)
    TYPE_MISMATCH = "type_mismatch"  # key of another type, or another RIHS01 type hash
    MALFORMED_CDR = "malformed_cdr"
    INVALID_ID = "invalid_id"  # a tracked id outside [A-Za-z0-9_.-]
    TF_NAN = "tf_nan"  # tf2's input checks, as its warnings name them
    TF_DENORMALIZED_QUATERNION = "tf_denormalized_quaternion"
    TF_SELF_TRANSFORM = "tf_self_transform"
    TF_NO_FRAME_ID = "tf_no_frame_id"
    TF_NO_CHILD_FRAME_ID = "tf_no_child_frame_id"
    TF_OLD_DATA = "tf_old_data"
    TF_REPEATED_DATA = "tf_repeated_data"
    TF_INVALID_STAMP = "tf_invalid_stamp"  # outside builtin_interfaces/Time's range
    TF_OUT_OF_RANGE = "tf_out_of_range"  # a translation beyond MAX_TRANSLATION_M
    TF_TOO_MANY_FRAMES = "tf_too_many_frames"  # over --ros-max-frames, none gone to forget
    TF_FRAME_NAME_TOO_LONG = "tf_frame_name_too_long"  # over MAX_FRAME_NAME characters


@dataclass(frozen=True, slots=True)
class Pose:
    """A validated pose: its stamp, and plain tuples the core can stack into arrays; unit
    quaternion. ``stance``: where the same human stands (translation, rotation), when this
    pose is where they look from another frame (a ROS4HRI person's face, its body
    apart); None when the two are one."""

    stamp: Time
    translation: tuple[float, float, float]
    rotation: tuple[float, float, float, float]
    stance: Stance | None = None


#: A human's stance: where their body stands, its translation and unit quaternion.
Stance = tuple[tuple[float, float, float], tuple[float, float, float, float]]


@dataclass(frozen=True, slots=True)
class Rejected:
    reason: Rejection
    detail: str


def _reason(error: ValidationError) -> Rejection:
    types = {e["type"] for e in error.errors(include_url=False)}
    if "json_invalid" in types:
        return Rejection.MALFORMED_JSON
    if "finite_number" in types:
        return Rejection.NON_FINITE
    return Rejection.SCHEMA


def _summary(error: ValidationError) -> str:
    first = error.errors(include_url=False)[0]
    where = ".".join(str(part) for part in first["loc"]) or "payload"
    return f"{where}: {first['msg']}"


def decode_pose(
    payload: bytes,
    body_id: str,
    frame_id: str,
    max_payload_bytes: int = DEFAULT_MAX_PAYLOAD_BYTES,
) -> Pose | Rejected:
    """Decode and validate one input payload for the key's ``(body_id, frame_id)``.

    Never raises on any input: every refusal is a ``Rejected`` with a reason and a short
    human-readable detail (for the rate-limited log, not per-sample logging).
    """
    if len(payload) > max_payload_bytes:
        return Rejected(Rejection.PAYLOAD_TOO_LARGE, f"{len(payload)} bytes > {max_payload_bytes}")
    fast = _plainly_valid(payload, body_id, frame_id)
    return fast if fast is not None else _decode_with_model(payload, body_id, frame_id)


def _decode_with_model(payload: bytes, body_id: str, frame_id: str) -> Pose | Rejected:
    """The authority: the pydantic model validates, and names what is wrong."""
    try:
        msg = TransformStamped.model_validate_json(payload)
    except ValidationError as error:
        return Rejected(_reason(error), _summary(error))
    if msg.header.frame_id != frame_id:
        return Rejected(
            Rejection.FRAME_MISMATCH,
            f"header.frame_id {msg.header.frame_id!r} != key frame {frame_id!r}",
        )
    if msg.child_frame_id not in ("", f"body_{body_id}"):
        return Rejected(
            Rejection.CHILD_FRAME_MISMATCH,
            f"child_frame_id {msg.child_frame_id!r} != 'body_{body_id}'",
        )
    q = msg.transform.rotation
    norm2 = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w
    if abs(norm2 - 1.0) > QUATERNION_TOLERANCE:
        return Rejected(Rejection.QUATERNION_NOT_NORMALIZED, f"|q|^2 = {norm2:.6g}, tolerance 0.01")
    norm = math.sqrt(norm2)
    t = msg.transform.translation
    return Pose(
        stamp=Time.from_model(msg.header.stamp),
        translation=(t.x, t.y, t.z),
        rotation=(q.x / norm, q.y / norm, q.z / norm, q.w / norm),
    )


class FastStamp(msgspec.Struct, gc=False):
    """A stamp for msgspec: bounds checked when decoding (the results encode it too)."""

    sec: Annotated[int, msgspec.Meta(ge=0, le=MAX_SEC)]
    nanosec: Annotated[int, msgspec.Meta(ge=0, le=MAX_NANOSEC)]


class _FastHeader(msgspec.Struct, gc=False):
    stamp: FastStamp
    frame_id: str


_Metres = Annotated[float, msgspec.Meta(ge=-MAX_TRANSLATION_M, le=MAX_TRANSLATION_M)]
_Component = Annotated[float, msgspec.Meta(ge=-2.0, le=2.0)]


class FastVector3(msgspec.Struct, gc=False):
    """A vector for msgspec: bounds checked when decoding (the results encode theirs
    with it too: encoding checks no bounds)."""

    x: _Metres
    y: _Metres
    z: _Metres


class _FastQuaternion(msgspec.Struct, gc=False):
    x: _Component
    y: _Component
    z: _Component
    w: _Component


class _FastTransform(msgspec.Struct, gc=False):
    translation: FastVector3
    rotation: _FastQuaternion


class _FastTransformStamped(msgspec.Struct, gc=False):
    header: _FastHeader
    transform: _FastTransform
    child_frame_id: str = ""


_FAST = msgspec.json.Decoder(_FastTransformStamped)


def _plainly_valid(payload: bytes, body_id: str, frame_id: str) -> Pose | None:
    """The pose of a payload the model would plainly accept, without building models;
    None for anything else, which the model then judges, so that every rejection keeps
    its exact reason and detail. Decoded by msgspec into typed, bounded structs shaped as
    the models (strict: ints or floats where the model takes floats, never bools;
    bounded, so finite), 0.35 us against the 0.9 us of pydantic's own parser alone and
    2.3 us with the checks in Python (each timed alone; the whole turn's gain is in
    benchmarks.perf.hot_path's figures, docs/performance.md); a test checks that whatever
    this accepts, the model accepts and decodes identically."""
    try:
        msg = _FAST.decode(payload)
    except (msgspec.DecodeError, UnicodeDecodeError):
        return None  # not JSON (nor UTF-8), a field missing or mistyped, a bound crossed
    header, child = msg.header, msg.child_frame_id
    if header.frame_id != frame_id or (child != "" and child != f"body_{body_id}"):
        return None
    t, q = msg.transform.translation, msg.transform.rotation
    qx, qy, qz, qw = q.x, q.y, q.z, q.w
    norm2 = qx * qx + qy * qy + qz * qz + qw * qw
    if abs(norm2 - 1.0) > QUATERNION_TOLERANCE:
        return None
    norm = math.sqrt(norm2)
    return Pose(
        Time(header.stamp.sec * NS_PER_S + header.stamp.nanosec),
        (t.x, t.y, t.z),
        (qx / norm, qy / norm, qz / norm, qw / norm),
    )
