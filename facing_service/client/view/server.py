"""The page's web server: aiohttp (a small, well-kept framework: HTTP, server-sent events,
static files) on 127.0.0.1 by default. ``GET /`` is the page, ``GET /events`` a stream of
snapshots (server-sent events): one at once, then one whenever it changes, checked
``PUSH_PERIOD_S``; a comment every ``KEEPALIVE_S`` lets the page tell a dead connection.
The browser's EventSource reconnects by itself, so the page recovers when the view does.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import threading
from collections.abc import Callable
from importlib import resources
from typing import Any

from aiohttp import web

PUSH_PERIOD_S = 0.1
KEEPALIVE_S = 2.0
STATIC = ("index.html", "view.js", "view.css")
TYPES = {"html": "text/html", "js": "text/javascript", "css": "text/css"}


def make_app(model: Callable[[], dict[str, Any]], stopping: threading.Event) -> web.Application:
    """The application: ``model()`` gives the current snapshot (called on the loop)."""
    files = {name: (resources.files(__package__) / "static" / name).read_bytes() for name in STATIC}

    async def page(request: web.Request) -> web.Response:
        name = request.match_info.get("name") or "index.html"
        if name not in files:
            raise web.HTTPNotFound()
        kind = TYPES[name.rsplit(".", 1)[-1]]
        return web.Response(body=files[name], content_type=kind, charset="utf-8",
                            headers={"Cache-Control": "no-store"})  # fmt: skip

    async def events(request: web.Request) -> web.StreamResponse:
        response = web.StreamResponse(
            headers={"Content-Type": "text/event-stream", "Cache-Control": "no-store"}
        )
        await response.prepare(request)
        with contextlib.suppress(ConnectionResetError):  # the page went away: nothing to say
            await _push(response)
        return response

    async def _push(response: web.StreamResponse) -> None:
        last, quiet = None, 0.0
        while not stopping.is_set():
            said = json.dumps(model(), separators=(",", ":"))
            if said != last:
                await response.write(f"data: {said}\n\n".encode())
                last, quiet = said, 0.0
            elif quiet >= KEEPALIVE_S:
                await response.write(b": keep-alive\n\n")
                quiet = 0.0
            await asyncio.sleep(PUSH_PERIOD_S)
            quiet += PUSH_PERIOD_S

    app = web.Application()
    app.router.add_get("/", page)
    app.router.add_get("/events", events)
    app.router.add_get("/{name}", page)
    return app


def serve(
    model: Callable[[], dict[str, Any]],
    host: str,
    port: int,
    stopping: threading.Event,
    started: Callable[[str], None] = lambda url: None,
) -> None:
    """Serve until ``stopping`` is set (blocking; its own event loop, any thread).
    Raises OSError when the address cannot be bound."""

    async def main() -> None:
        runner = web.AppRunner(make_app(model, stopping), handle_signals=False)
        await runner.setup()
        try:
            site = web.TCPSite(runner, host, port)
            await site.start()
            bound = runner.addresses[0][1]  # the port itself when asked for any (0)
            started(f"http://{_url_host(host)}:{bound}/")
            while not stopping.is_set():
                await asyncio.sleep(0.1)
        finally:
            await runner.cleanup()

    asyncio.run(main())


def _url_host(host: str) -> str:
    return f"[{host}]" if ":" in host else host
