"""Helpers to run facing-service on loopback: for this project's tests and benchmarks, and
for integrators' own integration tests (as ``numpy.testing`` is for numpy users).

Everything stays on 127.0.0.1 with multicast scouting off, so tests never reach, or are
reached by, anything else on the network.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from typing import IO

from .tools.loopback import endpoint, free_port, loopback_config, wait_for_port, wait_until

__all__ = [
    "LOOPBACK_FLAGS",
    "endpoint",
    "free_port",
    "loopback_config",
    "running_cli",
    "wait_for_port",
    "wait_until",
]

#: Flags that keep a service process on loopback and quick to start.
LOOPBACK_FLAGS = ("--no-multicast-scouting", "--cfg", "scouting/delay:0")


@contextmanager
def running_cli(
    *args: str,
    env: Mapping[str, str] | None = None,
    capture: bool = True,
    module: str = "facing_service",
    cwd: str | os.PathLike[str] | None = None,
    stdout: IO[str] | None = None,
) -> Iterator[subprocess.Popen[str]]:
    """``python -m <module> <args>`` as a real process (in ``cwd``); SIGTERM (then SIGKILL
    after 5 s) when the block ends. With ``capture``, stdout and stderr go to
    ``proc.stdout``; with ``stdout`` (a file, for a run too long to hold in a pipe), there."""
    into = subprocess.PIPE if capture else stdout
    proc = subprocess.Popen(
        [sys.executable, "-m", module, *args],
        env={**os.environ, **(env or {})},
        cwd=cwd,
        stdout=into,
        stderr=subprocess.STDOUT if into is not None else None,
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
