"""Helpers to run facing-service on loopback: for this project's tests and benchmarks, and
for integrators' own integration tests (as ``numpy.testing`` is for numpy users).

Everything stays on 127.0.0.1 with multicast scouting off, so tests never reach, or are
reached by, anything else on the network.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager

import zenoh

#: Flags that keep a service process on loopback and quick to start.
LOOPBACK_FLAGS = ("--no-multicast-scouting", "--cfg", "scouting/delay:0")


def free_port() -> int:
    """A TCP port free on 127.0.0.1 right now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
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


@contextmanager
def running_cli(
    *args: str,
    env: Mapping[str, str] | None = None,
    capture: bool = True,
    module: str = "facing_service",
    cwd: str | os.PathLike[str] | None = None,
) -> Iterator[subprocess.Popen[str]]:
    """``python -m <module> <args>`` as a real process (in ``cwd``); SIGTERM (then SIGKILL
    after 5 s) when the block ends. With ``capture``, stdout and stderr go to
    ``proc.stdout``."""
    proc = subprocess.Popen(
        [sys.executable, "-m", module, *args],
        env={**os.environ, **(env or {})},
        cwd=cwd,
        stdout=subprocess.PIPE if capture else None,
        stderr=subprocess.STDOUT if capture else None,
        text=True,
    )
    try:
        yield proc
    finally:
        if proc.poll() is None:
            proc.send_signal(signal.SIGTERM)
            try:
                proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
        if proc.stdout is not None:
            proc.stdout.close()
