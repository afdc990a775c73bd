"""The ROS4HRI tutorial's node, without ROS: every second, print the ids of the bodies
oriented toward the robot.

    python examples/facing_printer.py [-e tcp/<host>:7447] [--frame base_link]

With ROS4HRI this is an HRIListener, a loop over getBodies() and a tf transform per body;
here the facing-service does the geometry and the client keeps the answer up to date.
"""

from __future__ import annotations

import argparse
import time

from facing_service import FacingClient


def main() -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument(
        "-e", "--connect", action="append", default=[], metavar="ENDPOINT",
        help="the service's (or its router's) endpoint, e.g. tcp/127.0.0.1:7447; repeatable",
    )  # fmt: skip
    parser.add_argument("--frame", default="base_link", help="the base frame (default base_link)")
    parser.add_argument("--duration-s", type=float, help="stop after this long")
    args = parser.parse_args()

    with FacingClient(connect=args.connect, frame=args.frame) as hri:
        started = time.monotonic()
        while args.duration_s is None or time.monotonic() - started < args.duration_s:
            facing = hri.bodies_facing(args.frame)
            print(f"facing the robot: {' '.join(facing) if facing else '-'}", flush=True)
            time.sleep(1.0)


if __name__ == "__main__":
    main()
