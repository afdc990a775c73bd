"""Building input poses for tests: bodies placed in the base plane with a heading."""

from __future__ import annotations

import json
import math
from typing import Any


def yaw_quaternion(yaw_deg: float) -> tuple[float, float, float, float]:
    half = math.radians(yaw_deg) / 2.0
    return (0.0, 0.0, math.sin(half), math.cos(half))


def toward_origin_deg(x: float, y: float) -> float:
    """Heading (yaw) of a body at (x, y) whose chest points straight at the base origin."""
    return math.degrees(math.atan2(-y, -x))


def pose_dict(
    body_id: str,
    frame_id: str,
    x: float = 2.0,
    y: float = 0.0,
    yaw_deg: float | None = None,
    *,
    off_deg: float = 0.0,
    sec: int = 1,
    nanosec: int = 0,
    z: float = 0.0,
) -> dict[str, Any]:
    """A TransformStamped dict; by default the body looks at the robot, turned by off_deg."""
    yaw = (toward_origin_deg(x, y) if yaw_deg is None else yaw_deg) + off_deg
    qx, qy, qz, qw = yaw_quaternion(yaw)
    return {
        "header": {"stamp": {"sec": sec, "nanosec": nanosec}, "frame_id": frame_id},
        "child_frame_id": f"body_{body_id}",
        "transform": {
            "translation": {"x": x, "y": y, "z": z},
            "rotation": {"x": qx, "y": qy, "z": qz, "w": qw},
        },
    }


def pose_json(body_id: str, frame_id: str, **kwargs: Any) -> bytes:
    return json.dumps(pose_dict(body_id, frame_id, **kwargs)).encode()
