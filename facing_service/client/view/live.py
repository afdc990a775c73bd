"""The page against a running service: a FacingClient and a Watcher gather what the
service says, ``snapshot`` makes the page's model of it, ``server`` pushes it."""

from __future__ import annotations

import threading
from collections.abc import Callable

from ..client import FacingClient
from ..watch import Watcher
from .server import serve
from .snapshot import snapshot


def run_view(
    client: FacingClient,
    frame: str,
    host: str,
    port: int,
    stopping: threading.Event,
    started: Callable[[str], None] = lambda url: None,
) -> None:
    """Serve the page for ``frame`` until ``stopping`` (blocking)."""
    watcher = Watcher(client, frame)
    watcher.ask_frames()

    def model() -> dict:
        return snapshot(
            frame,
            watcher.people(),
            client.groups(frame),
            client.gazing(frame),
            bool(client.live_instances),
            watcher.frames(),
            client.greetings(frame),
            watcher.condition.note,
        )

    watcher.condition.start()
    try:
        serve(model, host, port, stopping, started)
    finally:
        watcher.condition.close()
