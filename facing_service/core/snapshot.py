"""The tracker and the scenes as one turn of the worker leaves them, read-only: what the
scenes, the ROS 2 output and its markers, and the queries read (the one read path),
instead of being handed the worker's tracker and scenes. Each part is worked out once,
when first asked for, and not at all on a turn that needs none (most turns: the scenes
and the ROS tick are due a few times a second)."""

from __future__ import annotations

from functools import cached_property

from ..contract.keys import BodyRef
from ..contract.levels import Level
from ..contract.poses import Pose
from ..contract.schemas import FrameFacing
from ..contract.stamps import ZERO, Time
from .records import BodyState, EngagementUpdate
from .social.scene import Person, Scenes, SceneUpdate
from .tracker import Tracker

#: The levels at which the robot may go and greet a person (in no group).
_ENGAGING = (Level.ENGAGING, Level.ENGAGED)


class TurnSnapshot:
    """Made by the worker after a turn's input and expiry, before anything reads it; the
    tracker does not change while it is read (one thread owns both)."""

    def __init__(self, tracker: Tracker, scenes: Scenes | None = None) -> None:
        self._tracker = tracker
        self._scenes = scenes
        self._poses: dict[str, list[tuple[str, Pose]]] = {}

    @cached_property
    def scenes(self) -> list[SceneUpdate]:
        """Every frame's current scene (groups, who faces whom), as last worked out."""
        return [] if self._scenes is None else self._scenes.current()

    @cached_property
    def engagements(self) -> list[EngagementUpdate]:
        """Every tracked body's engagement, as it stands."""
        return self._tracker.engagements()

    @cached_property
    def levels(self) -> dict[BodyRef, Level]:
        """Each tracked body's engagement level."""
        return {e.body: e.level for e in self.engagements}

    @cached_property
    def states(self) -> list[BodyState]:
        """Every tracked body's latest decision."""
        return self._tracker.states()

    @cached_property
    def frames(self) -> list[FrameFacing]:
        """Every frame's aggregate (who faces the robot, who is tracked)."""
        return self._tracker.frames()

    @cached_property
    def tracked(self) -> dict[str, int]:
        """How many bodies each frame tracks."""
        return self._tracker.tracked_per_frame()

    def evaluate(self, threshold_deg: float) -> tuple[list[BodyState], list[FrameFacing]]:
        """Every body and frame decided again under another cone (without hysteresis)."""
        return self._tracker.evaluate(threshold_deg)

    def empty_scene(self, frame_id: str) -> SceneUpdate | None:
        """A known frame's scene with nobody in it; None for a frame never seen."""
        return None if self._scenes is None else self._scenes.empty(frame_id)

    def poses(self, frame_id: str) -> list[tuple[str, Pose]]:
        """The latest pose of every body tracked in a frame, by body id."""
        if (poses := self._poses.get(frame_id)) is None:
            poses = self._poses[frame_id] = self._tracker.poses(frame_id)
        return poses

    def people(self, frame_id: str) -> tuple[list[Person], Time]:
        """A frame's people, as the scene sees them (where each stands, and where they look
        from when that is another frame), and their newest stamp."""
        poses = self.poses(frame_id)
        levels = self.levels
        people = [
            Person(
                body,
                *(p.stance or (p.translation, p.rotation)),
                levels.get(BodyRef(frame_id=frame_id, body_id=body)) in _ENGAGING,
                None if p.stance is None else (p.translation, p.rotation),
            )
            for body, p in poses
        ]
        return people, max((p.stamp for _, p in poses), default=ZERO)
