"""What the tracker takes in, keeps and gives out: plain records per pose, per body and per
frame, and the decision that turns poses into states (``decide``: the per-body formula for
a few bodies, the vectorized detector for many). Pure; the tracker owns the rules over time.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..contract.keys import BodyRef
from ..contract.levels import Level
from ..contract.poses import Pose
from ..contract.schemas import FrameFacing, facing_state_json
from ..contract.stamps import NS_PER_S, Time
from . import detector
from .engagement import Engagement, EngagementParams, Zone, zone


class _OfABody:
    """``frame_id`` and ``body_id`` read through a record's ``body`` (a BodyRef)."""

    __slots__ = ()
    body: BodyRef

    @property
    def frame_id(self) -> str:
        return self.body.frame_id

    @property
    def body_id(self) -> str:
        return self.body.body_id


@dataclass(frozen=True, slots=True)
class PoseSample(_OfABody):
    body: BodyRef
    pose: Pose
    profile: str = "body"  # which Profile decides it: "body", or "head" (a face frame)


@dataclass(frozen=True, slots=True)
class Profile:
    """How one kind of frame is decided: a chest faces in the horizontal plane (REP 155's
    body frame, the tutorial's rule), a head in 3D (people look down at a camera)."""

    threshold_deg: float
    hysteresis_deg: float
    cone3d: bool
    engagement: EngagementParams
    #: Decide on the median angle of the poses this long back (their stamps), not the
    #: last pose's alone (0: pose by pose). A face tracker's angle swings tens of degrees
    #: from frame to frame, which no cone's hysteresis holds; the median follows what
    #: most poses say, a turn about half the window later.
    facing_window_s: float = 0.0


@dataclass(frozen=True, slots=True)
class BodyState(_OfABody):
    """The decision for one body: the fields of the wire's ``FacingState``, kept as plain
    values (a pydantic model per sample was a third of the per-sample cost)."""

    body: BodyRef
    stamp: Time
    facing: bool
    angle_deg: float | None
    distance_m: float | None
    robot_in_body: tuple[float, float, float]
    threshold_deg: float
    position: tuple[float, float, float]
    heading_deg: float

    def to_json(self, instance: str | None = None) -> bytes:
        return facing_state_json(
            self.body_id,
            self.frame_id,
            self.stamp,
            self.facing,
            self.angle_deg,
            self.distance_m,
            self.robot_in_body,
            self.threshold_deg,
            self.position,
            self.heading_deg,
            instance,
        )


@dataclass(frozen=True, slots=True)
class EngagementUpdate(_OfABody):
    """A body's engagement to publish: ``previous`` is set when the level just changed
    (then it is also an event); UNKNOWN with a previous level means the body was lost."""

    body: BodyRef
    stamp: Time
    level: Level
    score: float
    zone: Zone
    since: Time
    previous: Level | None


@dataclass
class Changes:
    """What one tracker call changed, in the order it must be published."""

    results: list[BodyState] = field(default_factory=list)
    lost: list[BodyRef] = field(default_factory=list)
    frames: list[FrameFacing] = field(default_factory=list)
    out_of_order: list[PoseSample] = field(default_factory=list)
    over_capacity: list[PoseSample] = field(default_factory=list)
    engagement: list[EngagementUpdate] = field(default_factory=list)
    #: Poses on a body's new clock (its tracker restarted, see tracker.RESTART_EVIDENCE):
    #: the caller loses the body (no tombstone), then ingests them as a new life.
    restarted: list[PoseSample] = field(default_factory=list)


@dataclass(slots=True)
class Track:
    pose: Pose
    last_seen: float
    state: BodyState
    profile: Profile
    engagement: Engagement = field(default_factory=Engagement)
    engagement_published: float = float("-inf")  # the caller's clock, at the last update
    recent: Window = ()  # (stamp, angle) of the facing window

    def engagement_update(self, previous: Level | None) -> EngagementUpdate:
        """The body's engagement as published (``previous``: the level it changed from)."""
        state, engagement = self.state, self.engagement
        return EngagementUpdate(
            state.body,
            state.stamp,
            engagement.level,
            engagement.score,
            zone(state.distance_m, self.profile.engagement),
            Time.from_seconds(engagement.since),
            previous,
        )

    def __copy__(self) -> Track:
        """Shallow, as ``copy.copy`` was, without its generic path (a quarter of a
        one-pose batch went to the journal's copies)."""
        return Track(
            self.pose,
            self.last_seen,
            self.state,
            self.profile,
            self.engagement,
            self.engagement_published,
            self.recent,
        )


@dataclass
class Frame:
    """Who is tracked and who faces in one base frame. Its lists change through
    ``update`` and ``discard`` only: the tracker's journal keeps a frame once per
    transaction by ``__copy__``, which shares the sets (O(1) whatever the crowd: copying
    them cost 1.9 us a pose at 100 bodies and 314 us at 10 000), and the first change after
    it gives this frame sets of its own."""

    tracked: set[str] = field(default_factory=set)
    facing: set[str] = field(default_factory=set)
    stamp: Time | None = None
    dirty: bool = False  # membership changed since the aggregate was last published
    shared: bool = field(default=False, repr=False, compare=False)  # sets also a copy's

    def __copy__(self) -> Frame:
        self.shared = True
        return Frame(self.tracked, self.facing, self.stamp, self.dirty, True)

    def update(self, body_id: str, facing: bool) -> None:
        """``body_id`` is tracked here, facing or not; dirty when a list changes."""
        if body_id in self.tracked and (body_id in self.facing) == facing:
            return
        self._own()
        self.tracked.add(body_id)
        if facing:
            self.facing.add(body_id)
        else:
            self.facing.discard(body_id)
        self.dirty = True

    def discard(self, body_id: str) -> None:
        self._own()
        self.tracked.discard(body_id)
        self.facing.discard(body_id)
        self.dirty = True

    def _own(self) -> None:
        if self.shared:
            self.tracked, self.facing, self.shared = set(self.tracked), set(self.facing), False


def frame_facing(
    frame_id: str, stamp: Time | None, facing: Iterable[str], tracked: Iterable[str]
) -> FrameFacing:
    return FrameFacing(
        frame_id=frame_id,
        stamp=None if stamp is None else stamp.model(),
        bodies_facing=sorted(facing),
        bodies_tracked=sorted(tracked),
    )


#: A facing window: (stamp, angle) of a body's poses, oldest first.
Window = tuple[tuple[int, float], ...]
#: Most poses a facing window holds (a flood of poses must not make each decision cost
#: more): 2 s at 30 Hz.
MAX_WINDOW = 64


def through_window(
    track: Track | None, profile: Profile, stamp: int, angle: float | None, threshold_deg: float
) -> tuple[bool, Window]:
    """``windowed`` for a body's new pose (``track``: the body's, None when new), at
    ``threshold_deg`` (its hysteresis applied), with a window in its ``profile``."""
    was_facing = track is not None and track.state.facing
    recent = track.recent if track is not None else ()
    return windowed(recent, stamp, angle, profile.facing_window_s, threshold_deg, was_facing)


def windowed(
    recent: Window,
    stamp: int,
    angle: float | None,
    window_s: float,
    threshold_deg: float,
    was_facing: bool,
) -> tuple[bool, Window]:
    """Facing by the median angle of the poses in ``window_s`` up to ``stamp`` (this one,
    at ``angle``, included; an undefined angle counts as 180°), and the window kept. A
    face becomes facing when more than half its poses are inside ``threshold_deg``, and
    stays so while half of them are: a tracker alternating between two estimates, as
    many in as out, changes nothing either way."""
    since = stamp - window_s * NS_PER_S
    kept = [a for a in recent[-(MAX_WINDOW - 1) :] if a[0] > since]
    kept.append((stamp, 180.0 if angle is None else angle))
    angles = sorted(a[1] for a in kept)
    n = len(angles)
    median = angles[(n - 1) // 2] if was_facing else angles[n // 2]
    return median < threshold_deg, tuple(kept)


def decide(
    samples: Sequence[PoseSample],
    thresholds: Sequence[float],
    profiles: Sequence[Profile],
    reported: Sequence[float],
) -> list[BodyState]:
    """Decide ``samples`` (one threshold and profile each) and wrap each as a BodyState
    (reporting ``reported`` as its threshold): the vectorized core for a batch, the
    per-body one below ``detector.SMALL_BATCH``."""
    if len(samples) < detector.SMALL_BATCH:
        rows = [
            detector.classify_one(s.pose.translation, s.pose.rotation, threshold, p.cone3d)
            for s, threshold, p in zip(samples, thresholds, profiles, strict=True)
        ]
    else:
        result = detector.classify(
            np.array([s.pose.translation for s in samples], dtype=np.float64),
            np.array([s.pose.rotation for s in samples], dtype=np.float64),
            np.array(thresholds, dtype=np.float64),
            np.array([p.cone3d for p in profiles], dtype=np.bool_),
        )
        defined = result.defined.tolist()
        rows = [
            (tuple(r), a if d else None, m if d else None, f)
            for r, a, m, d, f in zip(
                result.robot_in_body.tolist(),
                result.angle_deg.tolist(),
                result.distance_m.tolist(),
                defined,
                result.facing.tolist(),
                strict=True,
            )
        ]
    return [
        BodyState(
            s.body,
            s.pose.stamp,
            facing,
            angle,
            distance,
            r,
            threshold,
            s.pose.translation,
            detector.heading_deg(s.pose.rotation),
        )
        for s, (r, angle, distance, facing), threshold in zip(samples, rows, reported, strict=True)
    ]
