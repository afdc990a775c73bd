"""Building input poses for tests: bodies placed in the base plane with a heading."""

from __future__ import annotations

import json
import math
from typing import Any

from facing_service.contract import poses as contract_poses
from facing_service.contract.stamps import Time

from loopback import send

#: The unit quaternion of a turn about z (the library's, named as the tests use it).
yaw_quaternion = contract_poses.yaw_rotation


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
    return contract_poses.pose_dict(
        body_id, frame_id, Time.of(sec, nanosec), (x, y, z), yaw_quaternion(yaw)
    )


def pose_json(body_id: str, frame_id: str, **kwargs: Any) -> bytes:
    return json.dumps(pose_dict(body_id, frame_id, **kwargs)).encode()


def replay(tracker, body: str, offs: list[float], start_s: float = 100.0) -> None:
    """A tracker's 30 Hz poses, each ``off`` degrees from facing the robot, stamped on the
    tracker's clock: engagement runs on stamps, so no test time is spent waiting."""
    for i, off in enumerate(offs):
        sec, nanosec = divmod(round((start_s + i / 30) * 1e9), 1_000_000_000)
        send(
            tracker,
            f"hri/bodies/{body}/pose/cam",
            pose_json(body, "cam", x=1.5, off_deg=off, sec=sec, nanosec=nanosec),
        )
