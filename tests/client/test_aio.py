"""An asyncio program with the client, over real zenoh sessions on loopback: before,
``hri.on_engaged(lambda ev: asyncio.create_task(greet(ev)))`` logged "no running event
loop" on every event, and open() held the loop for its whole timeout."""

from __future__ import annotations

import asyncio
import logging
import threading
import time

from facing_service import AsyncFacingClient
from facing_service.testing import endpoint, free_port

from loopback import send, wait_until_answered
from poses import pose_json


async def ticking(ticks: list[float], stop: asyncio.Event) -> None:
    """The loop's other work: a tick every 10 ms while it is free."""
    while not stop.is_set():
        ticks.append(time.monotonic())
        await asyncio.sleep(0.01)


def test_open_query_and_status_leave_the_loop_free_when_nothing_answers():
    async def program() -> tuple[int, bool]:
        ticks: list[float] = []
        stop = asyncio.Event()
        ticker = asyncio.create_task(ticking(ticks, stop))
        nobody = [endpoint(free_port())]
        client = AsyncFacingClient(frame="cam", connect=nobody, no_multicast_scouting=True,
                                   timeout_s=0.5)  # fmt: skip
        async with client:
            during_open = len(ticks)
            try:
                await client.status()
            except Exception as error:  # NoService: nobody there
                refused = type(error).__name__ == "NoService"
        stop.set()
        await ticker
        return during_open, refused

    during_open, refused = asyncio.run(program())
    assert during_open >= 10 and refused  # the loop ran on while open() waited 0.5 s


def test_an_asyncio_program_greets_on_engaged_with_no_traceback(net, caplog):
    caplog.set_level(logging.WARNING)
    _, ep = net.service()
    tracker = net.client(ep)
    wait_until_answered(tracker, "hri/facing/cam")
    facing = threading.Event()

    def track() -> None:  # a person facing the robot, 30 Hz, until told
        sec = 0
        while not facing.is_set() and sec < 30 * 20:
            sec += 1
            send(
                tracker,
                "hri/bodies/ann/pose/cam",
                pose_json("ann", "cam", sec=1 + sec // 30, nanosec=(sec % 30) * 33_000_000),
            )
            time.sleep(1 / 30)  # fmt: skip

    async def program() -> list[str]:
        greeted: list[str] = []
        done = asyncio.Event()

        async def greet(event) -> None:
            await asyncio.sleep(0)
            greeted.append(event.body_id)
            done.set()

        async with AsyncFacingClient(frame="cam", connect=[ep],
                                     no_multicast_scouting=True) as hri:  # fmt: skip
            hri.on_engaged(lambda ev: asyncio.create_task(greet(ev)))  # the issue's own line
            hri.on_engaged(greet)  # a coroutine function, run as a task
            feeding = asyncio.create_task(asyncio.to_thread(track))
            await asyncio.wait_for(done.wait(), timeout=20)
            await asyncio.sleep(0.1)
            facing.set()
            await feeding
        return greeted

    assert asyncio.run(program()) == ["ann", "ann"]
    said = [r.getMessage() for r in caplog.records]
    assert not [s for s in said if "event loop" in s or "never awaited" in s], said
