"""A tracker's side, in plain zenoh: publish the poses of two people 30 times a second,
as any body tracker would (docs/contract.md), one walking past the robot while turning
toward it, one standing still facing away.

    .venv/bin/python examples/tracker.py [-e tcp/<host>:7447] [--base-frame base_link]

Each pose is a TransformStamped as JSON on NS/bodies/<id>/pose/<frame>: the body's
position and orientation in the base frame. A DELETE on that key says the person left.
"""

from __future__ import annotations

import json
import math
import sys
import time

from common import arguments, run, session_config

# isort: split
# (after common, whose Ctrl-C handler covers this import)
import zenoh


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


def main() -> int:
    args = arguments(__doc__)
    with zenoh.open(session_config(args)) as session:
        # One publisher per body: a pose is a state change, never dropped (BLOCK); the
        # publisher also says whether anybody subscribes (zenoh's matching status).
        publishers = {
            body: session.declare_publisher(
                f"hri/bodies/{body}/pose/{args.frame}",
                encoding=zenoh.Encoding.APPLICATION_JSON,
                congestion_control=zenoh.CongestionControl.BLOCK,
            )
            for body in ("ann", "bob")
        }
        print(f"publishing ann and bob on hri/bodies/*/pose/{args.frame} 30 times a second"
              + (f" for {args.duration_s:g} s" if args.duration_s else " (Ctrl-C ends)"),
              flush=True)  # fmt: skip
        started, sent, heard = time.monotonic(), 0, 0
        try:
            while args.duration_s is None or time.monotonic() - started < args.duration_s:
                t = time.monotonic() - started
                y = 2.0 - (t % 8.0) / 2.0  # ann walks from 2 m left to 2 m right, every 8 s
                toward = math.atan2(-y, -2.0)  # facing the robot at the origin...
                publishers["ann"].put(pose("ann", args.frame, 2.0, y, toward, time.time()))
                publishers["bob"].put(pose("bob", args.frame, 3.0, -1.0, 0.0, time.time()))
                sent += 2
                # zenoh 1.10's stub says a bool; it is a MatchingStatus, as its docs say
                heard += 2 * publishers["ann"].matching_status.matching  # type: ignore[attr-defined]
                time.sleep(1 / 30)
        except KeyboardInterrupt:
            pass
        for publisher in publishers.values():  # both leave: a DELETE says so
            publisher.delete()
            publisher.undeclare()
    print(f"published {sent} poses, {heard} heard by a subscriber; ann and bob deleted")
    if not heard:  # sent to nowhere: not a success
        print("no subscriber heard them: is the facing service running, reachable from here?",
              file=sys.stderr)  # fmt: skip
        return 1
    return 0


if __name__ == "__main__":
    run(main)
