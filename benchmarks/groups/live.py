"""F-formations through the live service: the shared sequences fed as a tracker would
feed them, the groups read back from ``hri/groups/<frame>`` (the service's groups query).

Each annotated frame is held still for ``hold_s`` (1 s) at 30 Hz: every person's pose as
JSON on ``hri/bodies/p<id>/pose/<frame>`` (position in metres, heading as the body
frame's yaw), people absent from it DELETEd; at the end of that second the groups are
queried, so they must have settled within it. The robot stands at the base frame's
origin, as on a robot, a participant like anyone else.
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Sequence

import zenoh

from facing_service.config.settings import Settings
from facing_service.contract import keys
from facing_service.contract.poses import pose_dict, yaw_rotation
from facing_service.contract.stamps import Time
from facing_service.shell.service import FacingService
from facing_service.testing import endpoint, free_port, loopback_config, wait_until

FRAME = "fformation"
RATE_HZ = 30.0
BLOCK = zenoh.CongestionControl.BLOCK


def live(frames: Sequence, hold_s: float = 1.0) -> list[list[frozenset[int]]]:
    """The groups the service says at the end of each frame's hold (person ids)."""
    return [
        [frozenset(int(m.removeprefix("p")) for m in g["members"]) for g in said]
        for said in live_said(frames, hold_s)
    ]


def live_said(frames: Sequence, hold_s: float = 1.0) -> list[list[dict]]:
    """The groups the service says at the end of each frame's hold, as said (JSON: members
    as ``p<id>``, centre, join), the robot's own groups left out."""
    ep = endpoint(free_port())
    settings = Settings(
        listen=[ep],
        no_multicast_scouting=True,
        cfg=["scouting/delay:0"],
        base_frame=FRAME,
        instance="groups-evaluation",
        log_level="WARNING",
    )
    found: list[list[dict]] = []
    with FacingService(settings), zenoh.open(loopback_config(connect=[ep])) as tracker:
        wait_until(
            lambda: any(r.ok for r in tracker.get(keys.frame_key("hri", FRAME), timeout=0.5)),
            10.0,
            "the service",
        )
        present: set[int] = set()
        tick = 0
        for frame in frames:
            for gone in present - set(frame.ids):
                tracker.delete(
                    keys.pose_key("hri", body_id=f"p{gone}", frame_id=FRAME),
                    congestion_control=BLOCK,
                )
            present = set(frame.ids)
            start = time.monotonic()
            for k in range(round(hold_s * RATE_HZ)):
                tick += 1
                stamp = Time.from_seconds(tick / RATE_HZ)
                for i, (x, y), heading in zip(
                    frame.ids, frame.positions.tolist(), frame.headings.tolist(), strict=True
                ):
                    pose = pose_dict(
                        f"p{i}", FRAME, stamp, (x, y, 0.0), yaw_rotation(math.degrees(heading))
                    )
                    key = keys.pose_key("hri", body_id=f"p{i}", frame_id=FRAME)
                    tracker.put(key, json.dumps(pose), congestion_control=BLOCK)
                time.sleep(max(0.0, start + (k + 1) / RATE_HZ - time.monotonic()))
            found.append(_groups(tracker))
    return found


def _groups(session: zenoh.Session) -> list[dict]:
    """The service's groups of two people or more now, as said (the robot is no person)."""
    for reply in session.get(keys.groups_key("hri", FRAME), timeout=2.0):
        if reply.ok is not None:
            said = json.loads(reply.ok.payload.to_bytes())
            return [g for g in said["groups"] if len(g["members"]) > 1]
    return []
