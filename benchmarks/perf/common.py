"""What the measurement scripts share: running the real CLI, loopback sessions, poses."""

from __future__ import annotations

import json
import math
import subprocess
import time
from contextlib import AbstractContextManager
from pathlib import Path

import zenoh

from facing_service.contract import keys
from facing_service.contract.poses import pose_dict, yaw_rotation
from facing_service.contract.schemas import ServiceStatus
from facing_service.contract.stamps import Time
from facing_service.ros2 import types as ros2_types
from facing_service.testing import LOOPBACK_FLAGS, endpoint, free_port, loopback_config, running_cli

__all__ = ["free_port", "loopback_config"]  # re-exported for the scripts


def proc_status(pid: int) -> dict[str, str]:
    """A process's /proc status fields (Linux), read once: ``VmRSS``, ``Threads`` ..."""
    fields = (line.split(":", 1) for line in Path(f"/proc/{pid}/status").read_text().splitlines())
    return {name: value.strip() for name, value in fields}


def rss_mb(pid: int, status: dict[str, str] | None = None) -> float:
    """Resident memory of a process (from ``status`` when already read)."""
    return int((status or proc_status(pid))["VmRSS"].split()[0]) / 1024


def pose_payload(body: str, frame: str, x: float, y: float, yaw_deg: float, sec: int) -> bytes:
    return json.dumps(
        pose_dict(body, frame, Time.of(sec), (x, y, 0.0), yaw_rotation(yaw_deg))
    ).encode()


def tf_payload(body: str, frame: str, x: float, y: float, yaw_deg: float, sec: int) -> bytes:
    """The same pose as ``pose_payload``, as a robot sends it: a one-body TFMessage (CDR)."""
    half = math.radians(yaw_deg) / 2
    t = ros2_types.message_type
    message = t(ros2_types.TF_MESSAGE)(
        transforms=[
            t("geometry_msgs/msg/TransformStamped")(
                header=t("std_msgs/msg/Header")(
                    stamp=t("builtin_interfaces/msg/Time")(sec=sec, nanosec=0), frame_id=frame
                ),
                child_frame_id=f"body_{body}",
                transform=t("geometry_msgs/msg/Transform")(
                    translation=t("geometry_msgs/msg/Vector3")(x=x, y=y, z=0.0),
                    rotation=t("geometry_msgs/msg/Quaternion")(
                        x=0.0, y=0.0, z=math.sin(half), w=math.cos(half)
                    ),
                ),
            )
        ]
    )
    return ros2_types.serialize(message, ros2_types.TF_MESSAGE)


def ids_payload(ids: list[str]) -> bytes:
    t = ros2_types.message_type
    header = t("std_msgs/msg/Header")(
        stamp=t("builtin_interfaces/msg/Time")(sec=0, nanosec=0), frame_id=""
    )
    return ros2_types.serialize(t(ros2_types.IDS_LIST)(header=header, ids=ids), ros2_types.IDS_LIST)


def send(session: zenoh.Session, key: str, payload: bytes) -> None:
    session.put(key, payload, congestion_control=zenoh.CongestionControl.BLOCK)


def status(session: zenoh.Session, timeout: float = 2.0) -> ServiceStatus | None:
    for reply in session.get(keys.status_key("hri", "*"), timeout=timeout):
        if reply.ok is not None:
            return ServiceStatus.model_validate_json(reply.ok.payload.to_bytes())
    return None


def running_service(port: int, *flags: str) -> AbstractContextManager[subprocess.Popen[str]]:
    """The real CLI, as users run it, listening on a loopback port; quiet logs."""
    return running_cli(
        "run",
        "-l",
        endpoint(port),
        *LOOPBACK_FLAGS,
        "--log-level",
        "ERROR",
        *flags,
        capture=False,
    )


def wait_for_status(session: zenoh.Session, timeout: float = 20.0) -> ServiceStatus:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if (answer := status(session, timeout=0.5)) is not None:
            return answer
    raise SystemExit("the service never answered its status query")
