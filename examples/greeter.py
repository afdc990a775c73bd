"""A behaviour: greet people once when they start facing the robot, say goodbye when
they turn away for good or leave.

    .venv/bin/python examples/greeter.py [-e tcp/<host>:7447] [--base-frame base_link]

Transitions, not samples: on_facing fires once when someone turns toward the robot, not
30 times a second. A short grace period keeps a glance away from ending the conversation.
"""

from __future__ import annotations

import threading
import time

from common import arguments, run, say

from facing_service import BodyRef, FacingClient, FacingState

GRACE_S = 2.0  # turned away for less than this: still talking


class Greeter:
    def __init__(self) -> None:
        self.talking: dict[str, float | None] = {}  # id -> when they turned away, or None
        self.lock = threading.Lock()

    def hello(self, state: FacingState) -> None:
        with self.lock:
            if state.body_id not in self.talking:
                at = "" if state.distance_m is None else f" (at {state.distance_m:.1f} m)"
                say(f"hello {state.body_id}!{at}")
            self.talking[state.body_id] = None

    def turned_away(self, state: FacingState) -> None:
        with self.lock:
            if state.body_id in self.talking:
                self.talking[state.body_id] = time.monotonic()

    def lost(self, body: BodyRef) -> None:
        with self.lock:
            if self.talking.pop(body.body_id, "absent") != "absent":
                say(f"goodbye {body.body_id}")

    def tick(self) -> None:
        """Say goodbye to whoever has looked away for longer than the grace period."""
        now = time.monotonic()
        with self.lock:
            for body_id, since in list(self.talking.items()):
                if since is not None and now - since > GRACE_S:
                    del self.talking[body_id]
                    say(f"goodbye {body_id}")


def main() -> None:
    args = arguments(__doc__)

    greeter = Greeter()
    with FacingClient(connect=args.connect, frame=args.frame) as hri:
        hri.on_facing(greeter.hello)
        hri.on_not_facing(greeter.turned_away)
        hri.on_lost(greeter.lost)
        started = time.monotonic()
        while args.duration_s is None or time.monotonic() - started < args.duration_s:
            greeter.tick()
            time.sleep(0.1)


if __name__ == "__main__":
    run(main)
