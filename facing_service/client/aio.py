"""``AsyncFacingClient``: the client for an asyncio program.

    async with AsyncFacingClient(frame="base_link", connect=["tcp/10.0.0.2:7447"]) as hri:
        hri.on_engaged(greet)          # ``async def greet(event)``: run as a task
        print(hri.bodies_facing())     # the cache: a plain read, never waits
        states = await hri.query()     # the service asked, the loop free meanwhile

zenoh-python has no asyncio API, so this is ``FacingClient`` (its session, inbox and
dispatcher threads) with the waiting moved off the event loop: ``open``, ``close``,
``query`` and ``status`` wait in a worker thread (``asyncio.to_thread``), and each
callback is handed to the loop (``call_soon_threadsafe``), so it runs on the loop's
thread, where ``asyncio.create_task`` works; one that returns an awaitable (a coroutine
function) is run as a task, and what it raises is logged, not lost. Cache reads take a
lock held for microseconds: plain methods.
"""

from __future__ import annotations

import asyncio
import inspect
import logging
from collections.abc import Callable
from typing import Any

from typing_extensions import Unpack

from ..contract.errors import ClientNotOpen
from ..contract.levels import Level
from ..contract.schemas import FacingState, GazePair, Greeting, GroupState, ServiceStatus
from .client import FacingClient
from .options import ClientOptionFields
from .scene import ClientEvent

log = logging.getLogger("facing_service.client")

#: A callback: a plain function, or a coroutine function (run as a task on the loop).
Callback = Callable[..., object]


class AsyncFacingClient:
    """``FacingClient`` for asyncio; the same arguments (see ``FacingClient``). Use as an
    async context manager, or ``await open()`` then ``await close()``."""

    def __init__(
        self, namespace: str = "hri", frame: str = "*", **options: Unpack[ClientOptionFields]
    ) -> None:
        self.client = FacingClient(namespace, frame, **options)
        self._loop: asyncio.AbstractEventLoop | None = None
        self._tasks: set[asyncio.Task[object]] = set()  # running callbacks, kept alive

    async def open(self) -> AsyncFacingClient:
        """Open the client without blocking the loop (it may wait ``timeout_s`` for a
        service); callbacks then run on this loop."""
        self._loop = asyncio.get_running_loop()
        await asyncio.to_thread(self.client.open)
        return self

    async def close(self) -> None:
        """Close the client (its threads end; callbacks still queued are not run)."""
        await asyncio.to_thread(self.client.close)
        self._loop = None

    async def __aenter__(self) -> AsyncFacingClient:
        return await self.open()

    async def __aexit__(self, *_exc: object) -> None:
        await self.close()

    # -- asking the service: off the loop ---------------------------------------------

    async def query(
        self, frame: str | None = None, threshold_deg: float | None = None
    ) -> list[FacingState]:
        """``FacingClient.query``, awaited."""
        return await asyncio.to_thread(self.client.query, frame, threshold_deg)

    async def status(self) -> list[ServiceStatus]:
        """``FacingClient.status``, awaited."""
        return await asyncio.to_thread(self.client.status)

    # -- the cache: plain reads ----------------------------------------------------------

    def bodies(self, frame: str | None = None) -> dict[str, FacingState]:
        return self.client.bodies(frame)

    def bodies_facing(self, frame: str | None = None) -> list[str]:
        return self.client.bodies_facing(frame)

    def engagement(self, frame: str | None = None) -> dict[str, Level]:
        return self.client.engagement(frame)

    def groups(self, frame: str | None = None) -> list[GroupState]:
        return self.client.groups(frame)

    def greetings(self, frame: str | None = None) -> list[Greeting]:
        return self.client.greetings(frame)

    def gazing(self, frame: str | None = None) -> list[GazePair]:
        return self.client.gazing(frame)

    # -- callbacks, on the loop ------------------------------------------------------------

    def on(self, event: ClientEvent, callback: Callback) -> Callback:
        """``callback`` for ``event`` (as ``FacingClient.on_<event>``), run on the loop."""
        register = getattr(self.client, f"on_{event.value}")
        register(self._on_loop(callback))
        return callback

    def on_facing(self, callback: Callback) -> Callback:
        return self.on(ClientEvent.FACING, callback)

    def on_not_facing(self, callback: Callback) -> Callback:
        return self.on(ClientEvent.NOT_FACING, callback)

    def on_lost(self, callback: Callback) -> Callback:
        return self.on(ClientEvent.LOST, callback)

    def on_change(self, callback: Callback) -> Callback:
        return self.on(ClientEvent.CHANGE, callback)

    def on_engaged(self, callback: Callback) -> Callback:
        return self.on(ClientEvent.ENGAGED, callback)

    def on_disengaged(self, callback: Callback) -> Callback:
        return self.on(ClientEvent.DISENGAGED, callback)

    def on_group_formed(self, callback: Callback) -> Callback:
        return self.on(ClientEvent.GROUP_FORMED, callback)

    def on_group_changed(self, callback: Callback) -> Callback:
        return self.on(ClientEvent.GROUP_CHANGED, callback)

    def on_group_dissolved(self, callback: Callback) -> Callback:
        return self.on(ClientEvent.GROUP_DISSOLVED, callback)

    def on_robot_joined(self, callback: Callback) -> Callback:
        return self.on(ClientEvent.ROBOT_JOINED, callback)

    def on_robot_left(self, callback: Callback) -> Callback:
        return self.on(ClientEvent.ROBOT_LEFT, callback)

    def _on_loop(self, callback: Callback) -> Callable[..., None]:
        """What the client's dispatcher calls: hands the call to the loop."""
        loop = self._loop
        if loop is None:
            raise ClientNotOpen(
                "the AsyncFacingClient is not open: await open(), or use `async with`"
            )

        def hand_over(*args: object) -> None:
            if not loop.is_closed():
                loop.call_soon_threadsafe(self._run, callback, args)

        return hand_over

    def _run(self, callback: Callback, args: tuple[object, ...]) -> None:
        """On the loop: the call, and its coroutine as a task whose failure is logged."""
        try:
            result = callback(*args)
        except Exception:
            log.exception("facing client: callback %s failed", _name(callback))
            return
        if inspect.isawaitable(result):
            task = asyncio.ensure_future(_awaited(result))
            self._tasks.add(task)
            task.add_done_callback(self._done(callback))

    def _done(self, callback: Callback) -> Callable[[asyncio.Task[object]], None]:
        def done(task: asyncio.Task[object]) -> None:
            self._tasks.discard(task)
            if not task.cancelled() and (error := task.exception()) is not None:
                log.error("facing client: callback %s failed", _name(callback), exc_info=error)

        return done


async def _awaited(result: Any) -> object:
    """Any awaitable, as a coroutine (a task takes coroutines and futures alike)."""
    return await result


def _name(callback: Callback) -> str:
    return str(getattr(callback, "__qualname__", callback))
