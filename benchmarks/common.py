"""What the measurement scripts share: running the real CLI, loopback sessions, poses."""

from __future__ import annotations

import json
import math
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

import zenoh

from facing_service.schemas import ServiceStatus


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def loopback_config(connect: Sequence[str] = (), listen: Sequence[str] = ()) -> zenoh.Config:
    conf = zenoh.Config()
    conf.insert_json5("mode", '"peer"')
    conf.insert_json5("scouting/multicast/enabled", "false")
    conf.insert_json5("scouting/delay", "0")
    conf.insert_json5("connect/endpoints", json.dumps(list(connect)))
    conf.insert_json5("listen/endpoints", json.dumps(list(listen)))
    return conf


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


@contextmanager
def running_service(port: int, *flags: str) -> Iterator[subprocess.Popen]:
    """The real CLI, as users run it, listening on a loopback port; SIGTERM at the end."""
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "facing_service",
            "run",
            "-l",
            f"tcp/127.0.0.1:{port}",
            "--no-multicast-scouting",
            "--cfg",
            "scouting/delay:0",
            "--log-level",
            "ERROR",
            *flags,
        ],
    )
    try:
        yield proc
    finally:
        proc.send_signal(signal.SIGTERM)
        try:
            proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def wait_for_status(session: zenoh.Session, timeout: float = 20.0) -> ServiceStatus:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if (answer := status(session, timeout=0.5)) is not None:
            return answer
    raise SystemExit("the service never answered its status query")
