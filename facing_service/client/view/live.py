"""The page against a running service: a FacingClient and a Watcher gather what the
service says, ``snapshot`` makes the page's model of it, ``server`` pushes it."""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

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
    watcher = watching(client, frame)
    with watcher.condition:
        serve(lambda: page_model(watcher), host, port, stopping, started)


def watching(client: FacingClient, frame: str) -> Watcher:
    """What gathers the page's data for ``frame``, asked at once what it cannot hear."""
    watcher = Watcher(client, frame)
    watcher.ask_frames()
    return watcher


def page_model(watcher: Watcher) -> dict[str, Any]:
    """The page's model now (``snapshot``), from what the watcher and its client hold."""
    client, frame = watcher.client, watcher.frame
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
