"""zenoh on loopback: a free port, an endpoint, a session config that reaches nothing
else. The demo embeds a whole deployment this way; tests and benchmarks use the same
helpers through ``facing_service.testing``."""

from __future__ import annotations

import json
import socket
import time
from collections.abc import Callable, Sequence

import zenoh


def free_port(host: str = "127.0.0.1") -> int:
    """A TCP port free on ``host`` right now."""
    with socket.socket() as s:
        s.bind((host, 0))
        return s.getsockname()[1]


def endpoint(port: int) -> str:
    return f"tcp/127.0.0.1:{port}"


def loopback_config(
    listen: Sequence[str] = (), connect: Sequence[str] = (), mode: str = "peer"
) -> zenoh.Config:
    """A zenoh config for a session that only uses the given loopback endpoints."""
    conf = zenoh.Config()
    conf.insert_json5("mode", json.dumps(mode))
    conf.insert_json5("scouting/multicast/enabled", "false")
    conf.insert_json5("scouting/delay", "0")
    conf.insert_json5("listen/endpoints", json.dumps(list(listen)))
    conf.insert_json5("connect/endpoints", json.dumps(list(connect)))
    return conf


def wait_until(
    condition: Callable[[], bool], timeout: float, what: str, interval: float = 0.05
) -> None:
    """Poll ``condition`` until it holds; TimeoutError naming ``what`` after ``timeout``
    seconds. The one readiness loop of the tests and benchmarks (a port that listens, a
    queryable that answers, a service token that appears)."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() >= deadline:
            raise TimeoutError(f"{what}: not within {timeout:g} s")
        time.sleep(interval)


def wait_for_port(port: int, timeout: float = 10.0, host: str = "127.0.0.1") -> None:
    """Until something listens on ``host:port`` (a router process just started)."""

    def listens() -> bool:
        with socket.socket() as s:
            return s.connect_ex((host, port)) == 0

    wait_until(listens, timeout, f"a listener on port {port}", interval=0.02)
