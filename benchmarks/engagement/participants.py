"""One human, one participant, as a new user sees it: each shared recording
replayed into the real service (``--input ros2``, through a router, as
``benchmarks.engagement.recordings`` does), a ``FacingClient`` asked every quarter second
while it plays.

    python -m benchmarks.engagement.participants [--rate R] [--out FILE]

Per recording: the people in it (its labels), the participants said (the most ids
``bodies()`` held at once, and every id it ever held), the group answers (asks that found
a group) and those that grouped a human with their own face or body (two members standing
within ``SAME_HUMAN_M`` of each other: one head said twice), and asks whose people count
was more than the people in the recording.
"""

from __future__ import annotations

import argparse
import math
import threading
import time
from pathlib import Path
from typing import Any

import zenoh

from facing_service import FacingClient
from facing_service.config.settings import Settings
from facing_service.contract.schemas import FacingState, GroupState
from facing_service.ros2.wire import RosFormat, Wire
from facing_service.shell.service import FacingService
from facing_service.testing import endpoint, free_port, loopback_config
from facing_service.tools.replay import Replay

from .. import results_file
from . import scoring
from .recordings import _wait_for_service

#: Two members closer than this are one human said twice (a head's frames are one point;
#: two people never stand 15 cm apart).
SAME_HUMAN_M = 0.15
ASK_EVERY_S = 0.25


def self_grouped(group: GroupState, states: dict[str, FacingState]) -> bool:
    """Whether a group holds one human twice: two of its members at one place."""
    where = [states[m].position for m in group.members if m in states]
    return any(
        math.dist((a.x, a.y), (b.x, b.y)) < SAME_HUMAN_M
        for i, a in enumerate(where)
        for b in where[i + 1 :]
    )


def replayed(recording: scoring.Labelled, rate: float) -> dict[str, Any]:
    """What a client heard while the recording played into the real service."""
    ep = endpoint(free_port())
    settings = Settings(
        mode="client", connect=[ep], no_multicast_scouting=True, cfg=["scouting/delay:0"],
        input="ros2", base_frame=scoring.BASE_FRAME, instance="participants",
        log_level="WARNING",
    )  # fmt: skip
    asks: list[tuple[set[str], list[bool]]] = []  # (ids, each group: one human twice?)
    done = threading.Event()
    client_config = loopback_config(connect=[ep], mode="client")
    with (
        zenoh.open(loopback_config(listen=[ep], mode="router")),
        FacingService(settings),
        zenoh.open(client_config) as robot,
        FacingClient(frame=scoring.BASE_FRAME, session_config=client_config) as client,
    ):
        _wait_for_service(robot)

        def ask() -> None:
            while not done.wait(ASK_EVERY_S):
                states = client.bodies()
                asks.append((set(states), [self_grouped(g, states) for g in client.groups()]))

        asker = threading.Thread(target=ask, daemon=True)
        asker.start()
        try:
            with Replay(robot, recording.path, Wire(RosFormat.RMW_ZENOH)) as replay:
                replay.run(rate=rate)
            time.sleep(0.5)
        finally:
            done.set()
            asker.join()
    people = len(recording.persons)
    with_groups = [groups for _, groups in asks if groups]
    return {
        "people": people,
        "participants_at_once": max((len(ids) for ids, _ in asks), default=0),
        "participants_ever": sorted(set().union(*(ids for ids, _ in asks))),
        "asks": len(asks),
        "over_counted": sum(len(ids) > people for ids, _ in asks),
        "group_answers": len(with_groups),
        "self_groups": sum(any(groups) for groups in with_groups),
    }


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rate", type=float, default=1.0, help="replay rate (default 1)")
    parser.add_argument("--out", type=Path, help="write the results here (JSON)")
    args = parser.parse_args(argv)
    if not (math.isfinite(args.rate) and args.rate > 0):
        parser.error(f"--rate must be a positive number, got {args.rate}")
    results = {}
    print(f"{'recording':16} people  at once  ever  over-counted asks  self-groups / answers")
    for recording in scoring.labelled():
        r = results[recording.name] = replayed(recording, args.rate)
        print(
            f"{recording.name:16} {r['people']:6} {r['participants_at_once']:8} "
            f"{len(r['participants_ever']):5}  {r['over_counted']:5} of {r['asks']:4}  "
            f"{r['self_groups']:5} of {r['group_answers']}",
            flush=True,
        )
    if args.out is not None:
        command = "python -m benchmarks.engagement.participants"
        results_file.write(args.out, results, command, vars(args))
        print(f"written to {args.out}")


if __name__ == "__main__":
    main()
