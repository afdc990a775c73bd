"""``facing-service demo``: a whole deployment in one process, on loopback. An embedded
service, a simulated scene published into it as a tracker would, and the live view of the
results; nothing else needs to run."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from pathlib import Path

import zenoh

from ..client.client import FacingClient
from ..client.watch import Watcher
from ..config.settings import Settings
from ..shell.service import FacingService
from .loopback import endpoint, free_port, loopback_config

#: What puts people into the demo: ``feed(session, should_stop)`` publishes on ``session``
#: as a tracker (or a robot) would, until it is told to stop or has no more.
Feed = Callable[[zenoh.Session, Callable[[], bool]], object]


def run_demo(
    settings: Settings,
    feed: Feed,
    duration_s: float | None,
    stop: threading.Event,
    svg: Path | None = None,
    view_port: int | None = None,
) -> set[str]:
    """Until ``stop``, ``duration_s`` or the feed's end: the service in
    ``settings.base_frame``, the people ``feed`` publishes (a simulated scene, a camera),
    the terminal view, and the live page on ``view_port`` of 127.0.0.1 (None: no page).
    Returns who faced the robot meanwhile."""
    here = endpoint(free_port())
    embedded = _embedded(settings, here)
    frame = embedded.base_frame
    peer = loopback_config(connect=[here], mode="client")
    seen_facing: set[str] = set()
    with (
        FacingService(embedded),
        zenoh.open(peer) as tracker,
        FacingClient(embedded.namespace, frame, session_config=peer) as client,
    ):
        client.on_facing(lambda state: seen_facing.add(state.body_id))
        print(
            f"demo: the service answers on {here} (namespace {embedded.namespace}, frame "
            f"{frame}); another view or your code can join it: facing-service watch -m "
            f"client -e {here} --no-multicast-scouting --base-frame {frame}",
            flush=True,
        )
        watcher = Watcher(client, frame)
        page = None
        if view_port is not None:
            page = threading.Thread(
                target=_serve_page, args=(client, frame, view_port, stop), daemon=True
            )
            page.start()
        deadline = None if duration_s is None else time.monotonic() + duration_s

        def should_stop() -> bool:
            return stop.is_set() or (deadline is not None and time.monotonic() >= deadline)

        feeder = threading.Thread(target=feed, args=(tracker, should_stop), daemon=True)
        feeder.start()
        try:
            watcher.live(lambda: feeder.is_alive() and not stop.is_set())
            if svg is not None:
                watcher.save_svg(svg)
        finally:
            stop.set()
            feeder.join(timeout=2.0)
            if page is not None:
                page.join(timeout=2.0)
    return seen_facing


def _embedded(settings: Settings, here: str) -> Settings:
    """The embedded service's settings: a router on ``here``, the simulator and the views
    its clients. A router does not forward between peers (it expects them to mesh), so
    as peers the view would get results but never the poses it draws people from."""
    return settings.model_copy(
        update={
            "mode": "router",
            "listen": [here],
            "no_multicast_scouting": True,
            "cfg": ["scouting/delay:0"],
            "log_level": "WARNING",
        }
    )


def _serve_page(client: FacingClient, frame: str, port: int, stop: threading.Event) -> None:
    """The live page beside the terminal view; a port in use is said, not fatal."""
    from ..client.view.live import run_view  # aiohttp: loaded when a page is served

    try:
        run_view(client, frame, "127.0.0.1", port, stop, _offer)
    except OSError as error:
        print(f"demo: no live page on 127.0.0.1:{port} ({error.strerror}); "
              "choose another with --view-port", flush=True)  # fmt: skip


def _offer(url: str) -> None:
    print(f"demo: the live page is on {url}: open it in a browser", flush=True)
