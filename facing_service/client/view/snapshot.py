"""What the page shows at one instant, as the JSON pushed to it: pure, from what the
client gathered. Bounded: at most ``MAX_DRAWN`` people are sent (the nearest the robot),
the rest counted; ids go out as data, and the page shows them as text, never as markup.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from ...contract.keys import natural_order
from ...contract.schemas import GazePair, Greeting, GroupState
from ..watch import PersonView

#: People sent to the page at most: a crowd of thousands renders bounded.
MAX_DRAWN = 200


def snapshot(
    frame: str,
    people: Sequence[PersonView],
    groups: Sequence[GroupState],
    gazing: Sequence[GazePair],
    service_live: bool,
    elsewhere: Mapping[str, int],
    greetings: Sequence[Greeting] = (),
    input_note: str | None = None,
) -> dict[str, Any]:
    """The page's model: the frame, its people (nearest first, bounded), groups (with where
    to join each), who faces whom, where to greet whom, whether a service is alive, what
    its input gives when it is not heard (its people held: ``condition.input_note``), and
    the frames that have people."""
    nearest = sorted(people, key=lambda p: (math.hypot(p.x, p.y), natural_order(p.body_id)))
    drawn = nearest[:MAX_DRAWN]
    shown = {p.body_id for p in drawn}
    return {
        "frame": frame,
        "service": "live" if service_live else "lost",
        "input": input_note,
        "people": [
            {
                "id": p.body_id,
                "x": p.x,
                "y": p.y,
                "heading_deg": p.yaw_deg,
                "facing": p.facing,
                "angle_deg": p.angle_deg,
                "distance_m": p.distance_m,
                "threshold_deg": p.threshold_deg,
                "level": p.engagement or "UNKNOWN",
            }
            for p in sorted(drawn, key=lambda p: natural_order(p.body_id))
        ],
        "not_drawn": len(people) - len(drawn),
        "groups": [g.model_dump() for g in groups],
        "greetings": [g.model_dump() for g in greetings if g.body_id in shown],
        "gazing": [g.model_dump() for g in gazing if {g.sender, g.receiver} - {""} <= shown],
        "elsewhere": {f: n for f, n in sorted(elsewhere.items()) if f != frame and n},
    }
