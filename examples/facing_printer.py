"""The ROS4HRI tutorial's node, without ROS: every second, print the ids of the bodies
oriented toward the robot.

    .venv/bin/python examples/facing_printer.py [-e tcp/<host>:7447] [--base-frame base_link]

With ROS4HRI this is an HRIListener, a loop over getBodies() and a tf transform per body;
here the facing-service does the geometry and the client keeps the answer up to date.
"""

from __future__ import annotations

import time

from common import arguments, run, say

from facing_service import FacingClient


def main() -> None:
    args = arguments(__doc__)

    with FacingClient(connect=args.connect, frame=args.frame) as hri:
        started = time.monotonic()
        while args.duration_s is None or time.monotonic() - started < args.duration_s:
            facing = hri.bodies_facing()
            say(f"facing the robot: {' '.join(facing) if facing else '-'}")
            time.sleep(1.0)


if __name__ == "__main__":
    run(main)
