"""What the measurement scripts share: running the real CLI, loopback sessions, poses."""

from __future__ import annotations

import json
import math
import subprocess
import time
from contextlib import AbstractContextManager
from pathlib import Path

import zenoh

from facing_service.schemas import ServiceStatus
from facing_service.testing import LOOPBACK_FLAGS, endpoint, free_port, loopback_config, running_cli

__all__ = ["free_port", "loopback_config"]  # re-exported for the scripts


def rss_mb(pid: int) -> float:
    """Resident memory of a process, from /proc (Linux)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    raise RuntimeError(f"no VmRSS for pid {pid}")


def pose_payload(body: str, frame: str, x: float, y: float, yaw_deg: float, sec: int) -> bytes:
    half = math.radians(yaw_deg) / 2
    return json.dumps(
        {
            "header": {"stamp": {"sec": sec, "nanosec": 0}, "frame_id": frame},
            "child_frame_id": f"body_{body}",
            "transform": {
                "translation": {"x": x, "y": y, "z": 0.0},
                "rotation": {"x": 0.0, "y": 0.0, "z": math.sin(half), "w": math.cos(half)},
            },
        }
    ).encode()


def send(session: zenoh.Session, key: str, payload: bytes) -> None:
    session.put(key, payload, congestion_control=zenoh.CongestionControl.BLOCK)


def status(session: zenoh.Session, timeout: float = 2.0) -> ServiceStatus | None:
    for reply in session.get("hri/services/facing/*/status", timeout=timeout):
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
