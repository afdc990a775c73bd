"""A zenoh router in its own process (zenoh-python in router mode), for fault tests.

Spawned, never forked: forking after ``zenoh.open`` hangs the child.
"""

from __future__ import annotations

import multiprocessing
import os
import signal

import zenoh

from facing_service.testing import wait_for_port

_SPAWN = multiprocessing.get_context("spawn")


def _serve(config_json5: str) -> None:
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGTERM})
    session = zenoh.open(zenoh.Config.from_json5(config_json5))
    try:
        signal.sigwait({signal.SIGTERM})
    finally:
        session.close()


class Router:
    """``start()``, ``kill()`` (SIGKILL: a crash), ``stop()`` (SIGTERM)."""

    def __init__(self, config_json5: str, port: int) -> None:
        self.config_json5 = config_json5
        self.port = port
        self._process: multiprocessing.process.BaseProcess | None = None

    def start(self) -> Router:
        self._process = _SPAWN.Process(target=_serve, args=(self.config_json5,), daemon=True)
        self._process.start()
        wait_for_port(self.port)
        return self

    def kill(self) -> None:
        if self._process is not None and self._process.pid is not None:
            os.kill(self._process.pid, signal.SIGKILL)
            self._process.join(timeout=10)
            self._process = None

    def stop(self) -> None:
        if self._process is not None:
            self._process.terminate()
            self._process.join(timeout=10)
            if self._process.is_alive():
                self.kill()
            self._process = None
