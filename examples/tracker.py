"""A tracker's side, in plain zenoh: publish the poses of two people 30 times a second,
as any body tracker would (docs/contract.md), one walking past the robot while turning
toward it, one standing still facing away.

    python examples/tracker.py [-e tcp/<host>:7447] [--frame base_link]

Each pose is a TransformStamped as JSON on NS/bodies/<id>/pose/<frame>: the body's
position and orientation in the base frame. A DELETE on that key says the person left.
"""

from __future__ import annotations

import json
import math
import time

import zenoh
from common import arguments, session_config


def pose(body: str, frame: str, x: float, y: float, yaw: float, now: float) -> bytes:
    """The body's pose in ``frame``: at (x, y), its chest along ``yaw`` (radians)."""
    sec, nanosec = divmod(round(now * 1e9), 1_000_000_000)
    return json.dumps(
        {
            "header": {"stamp": {"sec": sec, "nanosec": nanosec}, "frame_id": frame},
            "child_frame_id": f"body_{body}",
            "transform": {
                "translation": {"x": x, "y": y, "z": 0.0},
                "rotation": {"x": 0.0, "y": 0.0, "z": math.sin(yaw / 2), "w": math.cos(yaw / 2)},
            },
        }
    ).encode()


def main() -> None:
    args = arguments(__doc__)
    block = zenoh.CongestionControl.BLOCK  # a pose is a state change: never dropped
    with zenoh.open(session_config(args)) as session:
        keys = {body: f"hri/bodies/{body}/pose/{args.frame}" for body in ("ann", "bob")}
        started = time.monotonic()
        while args.duration_s is None or time.monotonic() - started < args.duration_s:
            t = time.monotonic() - started
            y = 2.0 - (t % 8.0) / 2.0  # ann walks from 2 m left to 2 m right, every 8 s
            toward = math.atan2(-y, -2.0)  # facing the robot at the origin...
            session.put(keys["ann"], pose("ann", args.frame, 2.0, y, toward, time.time()),
                        congestion_control=block)  # fmt: skip
            session.put(keys["bob"], pose("bob", args.frame, 3.0, -1.0, 0.0, time.time()),
                        congestion_control=block)  # fmt: skip
            time.sleep(1 / 30)
        for key in keys.values():  # both leave
            session.delete(key, congestion_control=block)
        print("published", flush=True)


if __name__ == "__main__":
    main()
