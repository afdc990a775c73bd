"""Where should the robot go? Every second, print the place to join each group it is not
in, and to greet each person engaging with it in no group (x, y in metres and the way to
face in degrees, in the base frame): what a navigation goal is made of.

    .venv/bin/python examples/where_to_stand.py [-e tcp/<host>:7447] [--base-frame base_link]

The service works the places out from the people it sees (docs/groups.md, "Where to
stand"); a robot sends the one it chooses to its navigation as a goal.
"""

from __future__ import annotations

import math
import time

from common import arguments, run, say

from facing_service import FacingClient, Place


def said(place: Place) -> str:
    return f"({place.x:.2f}, {place.y:.2f}) facing {math.degrees(place.yaw):.0f}°"


def main() -> None:
    args = arguments(__doc__)

    with FacingClient(connect=args.connect, frame=args.frame) as hri:
        started = time.monotonic()
        while args.duration_s is None or time.monotonic() - started < args.duration_s:
            lines = []
            for group in hri.groups():
                who = ", ".join(group.members)
                if group.robot:
                    lines.append(f"in a group with {who}: stay")
                elif group.join is None:
                    lines.append(f"group of {who}: no room to join")
                else:
                    lines.append(f"to join {who}: stand at {said(group.join)}")
            for greeting in hri.greetings():
                lines.append(f"to greet {greeting.body_id}: stand at {said(greeting.place)}")
            say("; ".join(lines) or "nobody to join or greet")
            time.sleep(1.0)


if __name__ == "__main__":
    run(main)
