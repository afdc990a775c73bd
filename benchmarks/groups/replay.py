"""A sequence of frames replayed as a stream through the service's own scene (issue 70):
each frame's people held still from its arrival until the next, the scene worked out at
the service's rate as its loop would (``FrameScene.update``: skipped while nobody moves and
the memory has settled), the groups said read at the end of each frame's hold.

The core alone (no zenoh); ``live.live_said`` feeds the same frames to a running service.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

from facing_service.config.profiles import scene_params
from facing_service.config.settings import Settings
from facing_service.contract.poses import yaw_rotation
from facing_service.contract.stamps import Time
from facing_service.core.social.memory import MemoryParams
from facing_service.core.social.scene import ROBOT, FrameScene, Person, SceneParams

from .sequence_frame import Frame

Said = list[frozenset[int]]  # the groups of two people or more, by person id


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


def replay(
    frames: Sequence[Frame], spacing_s: float, params: SceneParams, before_s: float = 0.0
) -> list[Said]:
    """The groups said at the end of each frame's ``spacing_s`` hold; the first frame's
    people stood as they are for ``before_s`` before it (a made scene's people were there
    before it starts: its first frames are not the service's first sight of them)."""
    scene = FrameScene("replay", params)
    now, out = 0.0, []
    for k, frame in enumerate(frames):
        standing = people(frame)
        hold = spacing_s + (before_s if k == 0 else 0.0)
        ticks = max(1, round(hold / params.period_s))
        for _ in range(ticks):
            scene.update(standing, Time.from_seconds(now), now)
            now += hold / ticks
        out.append(said(scene))
    return out


def said(scene: FrameScene) -> Said:
    """The scene's groups as said, the robot left out (it is no person of the data)."""
    out = []
    for group in scene.tracker.groups.values():
        persons = frozenset(int(m.removeprefix("p")) for m in group.members if m != ROBOT)
        if len(persons) > 1:
            out.append(persons)
    return out
