"""A sequence of frames replayed as a stream through the service's own scene:
each frame's people held still from its arrival until the next, the scene worked out at
the service's rate as its loop would (``FrameScene.update``: skipped while nobody moves and
the memory has settled), the groups said read at the end of each frame's hold.

The core alone (no zenoh); ``live.live_said`` feeds the same frames to a running service.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import replace

from facing_service.config.profiles import scene_params
from facing_service.config.settings import Settings
from facing_service.contract.poses import yaw_rotation
from facing_service.contract.stamps import Time
from facing_service.core.social.memory import MemoryParams
from facing_service.core.social.scene import ROBOT, FrameScene, Person, SceneParams

from .sequence_frame import Frame

Said = list[frozenset[int]]  # the groups of two people or more, by person id
FRAME = "replay"


def shipped(memory: MemoryParams | None = None) -> SceneParams:
    """The service's default scene, with another memory where given."""
    params = scene_params(Settings())
    return params if memory is None else replace(params, memory=memory)


def people(frame: Frame) -> list[Person]:
    """A frame's people as the service has them: ``p<id>``, the heading as the body's yaw."""
    return [
        Person(f"p{i}", (x, y, 0.0), yaw_rotation(math.degrees(h)))
        for i, (x, y), h in zip(frame.ids, frame.positions.tolist(), frame.headings.tolist(),
                                strict=True)
    ]  # fmt: skip


def held(
    frames: Sequence[Frame], spacing_s: float, params: SceneParams, before_s: float = 0.0
) -> Iterator[FrameScene]:
    """The scene at the end of each frame's ``spacing_s`` hold, worked out at the
    service's rate; the first frame's people stood as they are for ``before_s`` before it."""
    scene = FrameScene(FRAME, params)
    now = 0.0
    for k, frame in enumerate(frames):
        standing = people(frame)
        hold = spacing_s + (before_s if k == 0 else 0.0)
        ticks = max(1, round(hold / params.period_s))
        for _ in range(ticks):
            scene.update(standing, Time.from_seconds(now), now)
            now += hold / ticks
        yield scene


def replay(
    frames: Sequence[Frame], spacing_s: float, params: SceneParams, before_s: float = 0.0
) -> list[Said]:
    """The groups said at the end of each frame's ``spacing_s`` hold; the first frame's
    people stood as they are for ``before_s`` before it (a made scene's people were there
    before it starts: its first frames are not the service's first sight of them)."""
    return [said(scene) for scene in held(frames, spacing_s, params, before_s)]


def said_with_places(frames: Sequence[Frame], hold_s: float) -> list[list[dict]]:
    """``live.live_said``'s answer from the service's scene alone: each frame held
    ``hold_s``, the groups of two people or more said at its end as the service publishes
    them (members ``p<id>``, the robot left out; where to join, or None)."""
    out = []
    for scene in held(frames, hold_s, shipped()):
        out.append([
            {"members": sorted(persons), "join": None if g.join is None else
             {"x": g.join.x, "y": g.join.y, "yaw": g.join.yaw}}
            for g in scene.snapshot().groups
            if len(persons := [m for m in g.members if m != ROBOT]) > 1
        ])  # fmt: skip
    return out


def said(scene: FrameScene) -> Said:
    """The scene's groups as said, the robot left out (it is no person of the data)."""
    out = []
    for group in scene.tracker.groups.values():
        persons = frozenset(int(m.removeprefix("p")) for m in group.members if m != ROBOT)
        if len(persons) > 1:
            out.append(persons)
    return out
