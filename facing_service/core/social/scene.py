"""The social scene of each base frame: who faces whom, and who stands in a group with whom,
the robot one of the people (at the frame's origin, facing +x; its id is ``ROBOT``, "",
as REP 155's Gaze and Group messages say it).

Pure: the caller gives the people and the clock. Bounded: a frame's scene is worked out at
most once a ``period_s`` (pairwise work is O(N²)), on its ``max_people`` nearest the robot
(the rest counted in ``left_out``), and said only when it changed: a pair that starts or
stops facing (with the facing rule's hysteresis), a grouping that has held ``hold_s``.

Where the robot should stand: for each group it is not in, the place on the
group's ring to join it (``core.social.join``); for each person ENGAGING or ENGAGED and in no
group as said (never one of a group said beside it), a place in front of them at
``greet_m``, facing them. Both follow the people
without being changes of their own (a query, or the next update, says where they are
now); a person to greet who appears or goes is a change of the frame's groups.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Protocol

import numpy as np

from ...contract.poses import Stance
from ...contract.stamps import ZERO, Time
from .. import detector
from .groups import (
    Group,
    GroupParams,
    GroupTracker,
    RoomScale,
    ScaleParams,
    detect,
    members,
    on_the_ring,
    vote_centres,
)
from .join import JoinParams, JoinPose, clearance, join_pose, o_space
from .memory import MemoryParams, SceneMemory
from .vacancy import Vacancies

ROBOT = GroupTracker.ROBOT
_ROBOT_POSE = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))


@dataclass(frozen=True, slots=True)
class SceneParams:
    groups: GroupParams
    scale: ScaleParams  # the room's unit of length, learnt from its people
    threshold_deg: float  # who faces whom: the facing rule's cone, with a person for the robot
    hysteresis_deg: float
    hold_s: float  # a new grouping is said once it has held this long
    period_s: float  # a frame's scene is worked out at most once a period
    max_people: int  # the people of one frame considered (nearest the robot first)
    join: JoinParams = field(default_factory=JoinParams)  # where to stand to join a group
    greet_m: float = 1.2  # how far in front of a person the robot stands to greet them
    # What the last seconds say: headings and pairs as evidence over time.
    memory: MemoryParams = field(default_factory=MemoryParams)


@dataclass(frozen=True, slots=True)
class Person:
    """One participant: where they stand (groups, where to stand) and, when it is another
    frame, where they look from (``look``: a ROS4HRI person's face beside its body; who
    faces whom reads it)."""

    id: str
    translation: tuple[float, float, float]
    rotation: tuple[float, float, float, float]  # (x, y, z, w): x is where the person faces
    engaging: bool = False  # ENGAGING or ENGAGED: one the robot may go and greet
    look: Stance | None = None  # (translation, rotation); None: where they stand

    def looking(self) -> Stance:
        return self.look or (self.translation, self.rotation)


class PeopleOf(Protocol):
    """Where a frame's people are read from (the worker's turn snapshot)."""

    def people(self, frame_id: str) -> tuple[list[Person], Time]: ...


Pair = tuple[str, str]  # (sender, receiver): the sender faces the receiver


@dataclass(frozen=True, slots=True)
class PlaceToGreet:
    """Where the robot should stand to greet a person engaging with it, in no group."""

    body_id: str
    pose: JoinPose


@dataclass(frozen=True, slots=True)
class SceneUpdate:
    """What changed in one frame's scene, and the whole scene as it now stands."""

    frame_id: str
    stamp: Time
    groups: tuple[Group, ...]  # every group, by id
    changed: tuple[Group, ...]  # formed (a new id) or with other members
    dissolved: tuple[int, ...]
    gazing: frozenset[Pair]
    groups_changed: bool  # the frame's groups are to be said (changed, or said first)
    gazing_changed: bool  # who faces whom is to be said
    left_out: int  # people beyond max_people, not considered
    greetings: tuple[PlaceToGreet, ...] = ()  # people engaging, in no group: where to greet them


#: Nobody moved when no position changed by more than this (m) and no rotation by more
#: than this (quaternion components): a tracker re-sending still people costs no scene.
STILL_M, STILL_Q = 1e-3, 1e-4


@dataclass(frozen=True)
class LastComputation:
    """What the last computation was given, and the groups it found."""

    ids: list[str]
    t: np.ndarray
    q: np.ndarray
    engaging: list[bool]
    heading: np.ndarray
    found: list[tuple[frozenset[str], tuple[float, float]]]
    greetings: tuple[PlaceToGreet, ...]

    def still(self, ids: list[str], t: np.ndarray, q: np.ndarray, engaging: list[bool]) -> bool:
        return (
            ids == self.ids
            and engaging == self.engaging
            and bool(np.all(np.abs(t - self.t) <= STILL_M))
            and bool(np.all(np.abs(q - self.q) <= STILL_Q))
        )


@dataclass
class FrameScene:
    """One base frame's scene between updates."""

    frame_id: str
    params: SceneParams
    tracker: GroupTracker = field(init=False)
    room: RoomScale = field(init=False)
    gazing: frozenset[Pair] = frozenset()
    left_out: int = 0
    greetings: tuple[PlaceToGreet, ...] = ()
    stamp: Time = ZERO
    said_once: bool = False
    _worked: LastComputation | None = None
    # Where to join each group, worked out from the last computation's people when a
    # group is said or read (most computations are neither), then kept until the next.
    _joins: dict[frozenset[str], JoinPose | None] = field(default_factory=dict)
    _vacancies: Vacancies = field(default_factory=Vacancies)  # places members just left
    memory: SceneMemory = field(init=False)

    def __post_init__(self) -> None:
        self.tracker = GroupTracker(self.params.hold_s)
        self.room = RoomScale(self.params.scale)
        self.memory = SceneMemory(self.params.memory, self.params.period_s)

    @property
    def pending(self) -> bool:
        """A grouping waits to be said (it must be looked at again once it has held), or
        the memory is still settling (time alone changes the groups: people standing still
        are looked at again)."""
        return self.tracker.pending or not self.memory.settled

    def update(self, people: Sequence[Person], stamp: Time, now: float) -> SceneUpdate | None:
        """The scene of ``people`` now; an update when anything said changed."""
        p = self.params
        # everyone here, the crowd's cut too: a member not among them was said gone
        present = {person.id for person in people} | {ROBOT}
        people, left_out = nearest(people, p.max_people)
        ids = [person.id for person in people] + [ROBOT]
        t = np.array([person.translation for person in people] + [_ROBOT_POSE[0]])
        q = np.array([person.rotation for person in people] + [_ROBOT_POSE[1]])
        looks = [person.looking() for person in people] + [_ROBOT_POSE]
        look_t, look_q = np.array([lt for lt, _ in looks]), np.array([lq for _, lq in looks])
        engaging = [person.engaging for person in people]
        where = np.hstack([t, look_t]), np.hstack([q, look_q])  # what a move may change
        moved = self._worked is None or not self._worked.still(ids, *where, engaging)
        if self._worked is not None and not moved and self.memory.settled:
            gazing, found = self.gazing, self._worked.found  # nothing to redo
            greetings = self._worked.greetings
        else:
            gazing = self._who_faces_whom(ids, look_t, look_q)
            scale = self.room.observe(t[:-1, :2], now)  # the people's spacing, not the robot's
            heading = self.memory.headings(ids, detector.headings(q), now)
            now_labels = detect(t[:, :2], heading, p.groups, scale)
            robot = len(ids) - 1
            ringed = on_the_ring(now_labels, t[:, :2], heading, p.groups, scale, robot)
            labels = self.memory.groups(ringed, t[:, :2])  # what the last seconds say
            centre = vote_centres(t[:, :2], heading, labels, p.groups, scale)
            found = [
                (frozenset(ids[i] for i in m), (x, y))
                for m, (x, y) in zip(members(labels), centre.tolist(), strict=True)
            ]
            greetings = _greetings(ids, t[:, :2], heading, engaging, labels, p)
            self._worked = LastComputation(ids, *where, engaging, heading, found, greetings)
            self._joins = {}
        before = self.tracker.groups
        # a grouping held long enough, or someone said gone
        changed, dissolved = self.tracker.update(found, now, present)
        if moved or changed or dissolved:  # where the said groups' members stand, who left
            self._seen_seated(before, found)
        # A greeting is for a person in no group *as said*: the groups said lag this
        # reading by ``hold_s``, so a person alone in it may still be in a said group
        # (one answer held a group of p3 and the robot, and a greeting for p3).
        grouped = {m for group in self.tracker.groups.values() for m in group.members}
        greetings = tuple(g for g in greetings if g.body_id not in grouped)
        first_or_cut = not self.said_once or left_out != self.left_out
        greeted = {g.body_id for g in greetings} != {g.body_id for g in self.greetings}
        groups_changed = first_or_cut or bool(changed or dissolved) or greeted
        gazing_changed = first_or_cut or gazing != self.gazing
        # The newest stamp behind the scene, kept while nothing changes too: people who
        # stood still and then left are said gone at their last pose's stamp, not at the
        # stamp of the last change. Never back: a person with the newest stamp
        # leaving does not make the scene older than what was said.
        self.stamp = max(self.stamp, stamp)
        self.greetings = greetings  # they follow the people: no change of their own
        if not (groups_changed or gazing_changed):
            return None
        self.gazing, self.left_out, self.said_once = gazing, left_out, True
        return self.snapshot(changed, dissolved, groups_changed, gazing_changed, groups_changed)

    def _seen_seated(
        self, before: dict[int, Group], found: list[tuple[frozenset[str], tuple[float, float]]]
    ) -> None:
        """Where the said groups' members stand, and the place one who left stood in."""
        worked = self._worked
        assert worked is not None  # (an update has worked the people out by now)
        where = dict(zip(worked.ids[:-1], map(tuple, worked.t[:-1, :2].tolist()), strict=True))
        self._vacancies.seen(self.tracker.groups, before, {m for m, _ in found}, where)

    def snapshot(
        self,
        changed: Sequence[Group] = (),
        dissolved: Sequence[int] = (),
        groups_changed: bool = False,
        gazing_changed: bool = False,
        joins: bool = True,
    ) -> SceneUpdate:
        """The scene as last said, with what its last update changed; each group with
        where to join it, unless ``joins`` is off (an update that says only who faces
        whom: its groups are not said, and working the places out would cost for nothing)."""

        def placed(group: Group) -> Group:
            return replace(group, join=self._join(group)) if joins else group

        groups = sorted(self.tracker.groups.values(), key=lambda g: g.id)
        return SceneUpdate(
            self.frame_id,
            self.stamp,
            tuple(map(placed, groups)),
            tuple(map(placed, changed)),
            tuple(dissolved),
            self.gazing,
            groups_changed,
            gazing_changed,
            self.left_out,
            self.greetings,
        )

    def _join(self, group: Group) -> JoinPose | None:
        """Where the robot should stand to join a group it is not in (None: it is in it,
        or the group has no room), from the last computation's people: everyone else but
        the robot is in the way. Worked out once per computation, when asked."""
        worked = self._worked
        if group.robot or worked is None:
            return None
        if group.members not in self._joins:
            xy = worked.t[:, :2]
            index = {person: i for i, person in enumerate(worked.ids[:-1])}  # the robot last
            inside = [index[m] for m in sorted(group.members) if m in index]
            others = [i for i in index.values() if i not in inside]
            self._joins[group.members] = None if len(inside) < 2 else self._place_in(
                group.id, xy[inside], worked.heading[inside], xy[others]
            )  # fmt: skip
        return self._joins[group.members]

    def _place_in(
        self, gid: int, inside: np.ndarray, headings: np.ndarray, others: np.ndarray
    ) -> JoinPose | None:
        """The place a member of group ``gid`` just left, while nobody takes it and the
        group stays; else the place the group's ring offers (``join_pose``)."""
        p = self.params.join
        if gid in self._vacancies:  # (most groups have none: no cost)
            clear_m = clearance(inside, p)
            left = self._vacancies.place(gid, inside, others, clear_m, p.min_clearance_m)
            if left is not None:
                centre, _ = o_space(inside, headings, p)
                yaw = math.atan2(centre[1] - left[1], centre[0] - left[0])
                return JoinPose(left[0], left[1], yaw)
        return join_pose(inside, headings, others, (0.0, 0.0), p)

    def _who_faces_whom(self, ids: list[str], t: np.ndarray, q: np.ndarray) -> frozenset[Pair]:
        """Pairs (a, b) with b in a's cone; a pair already said keeps facing within the
        hysteresis, as a body facing the robot does."""
        p = self.params
        n = len(ids)
        index = {person: i for i, person in enumerate(ids)}
        threshold = np.full((n, n), p.threshold_deg)
        for a, b in self.gazing:
            if a in index and b in index:
                threshold[index[a], index[b]] += p.hysteresis_deg
        facing = detector.facing_matrix(t, q, threshold)
        return frozenset((ids[a], ids[b]) for a, b in zip(*np.nonzero(facing), strict=True))


def _greetings(
    ids: list[str],
    xy: np.ndarray,
    heading: np.ndarray,
    engaging: list[bool],
    labels: np.ndarray,
    p: SceneParams,
) -> tuple[PlaceToGreet, ...]:
    """For each person engaging (the robot last in ``ids``) and in no group: the place
    ``greet_m`` in front of them, facing them, when nobody else stands nearer to it than
    the join's least clearance."""
    out = []
    alone = np.bincount(labels)[labels] == 1
    for i, person in enumerate(ids[:-1]):
        if not (engaging[i] and alone[i]):
            continue
        ahead = np.array([math.cos(heading[i]), math.sin(heading[i])])
        place = xy[i] + p.greet_m * ahead
        others = np.delete(xy[:-1], i, axis=0)
        if len(others) and np.hypot(*(others - place).T).min() < p.join.min_clearance_m:
            continue
        yaw = math.atan2(-ahead[1], -ahead[0])
        out.append(PlaceToGreet(person, JoinPose(float(place[0]), float(place[1]), yaw)))
    return tuple(out)


def nearest(people: Sequence[Person], most: int) -> tuple[list[Person], int]:
    """At most ``most`` people, nearest the robot first; how many were left out."""
    if len(people) <= most:
        return list(people), 0
    kept = sorted(people, key=lambda p: p.translation[0] ** 2 + p.translation[1] ** 2)[:most]
    return kept, len(people) - most


class Scenes:
    """Every base frame's scene: which are due to be worked out, and their updates; the
    frames emptied lately are remembered (``PAST_FRAMES`` of them, with their last stamp),
    so that a query on one is answered "nobody there", not "no such frame"."""

    PAST_FRAMES = 256

    def __init__(self, params: SceneParams) -> None:
        self._past: OrderedDict[str, Time] = OrderedDict()
        self.params = params
        self._frames: dict[str, FrameScene] = {}
        self._dirty: set[str] = set()  # frames whose people moved since last worked out
        self._due: dict[str, float] = {}  # frame -> earliest time it may be worked out again
        self._pending: set[str] = set()  # frames with a grouping waiting to have held

    def touch(self, frame_ids: set[str]) -> None:
        """The people of these frames changed (a pose, a person lost)."""
        self._dirty |= frame_ids

    def next_due(self) -> float | None:
        """When the next frame may be worked out (the caller's clock), if any waits.
        Asked on every turn of the service's loop: nothing to do costs a truth test."""
        if not (self._dirty or self._pending):
            return None
        return min(self._due.get(f, float("-inf")) for f in self._dirty | self._pending)

    def tick(self, now: float, snapshot: PeopleOf) -> list[SceneUpdate]:
        """Work out every frame that is due; the updates of those that changed.
        ``snapshot.people(frame)`` gives a frame's people and their newest stamp (the
        worker's ``snapshot.TurnSnapshot``)."""
        if not (self._dirty or self._pending):
            return []
        out = []
        for frame_id in sorted(self._dirty | self._pending):
            if self._due.get(frame_id, float("-inf")) > now:
                continue
            self._dirty.discard(frame_id)
            self._due[frame_id] = now + self.params.period_s
            people, stamp = snapshot.people(frame_id)
            scene = self._frames.get(frame_id) or FrameScene(frame_id, self.params)
            self._frames[frame_id] = scene
            update = scene.update(people, stamp, now)
            if update is not None:
                out.append(update)
            if scene.pending:
                self._pending.add(frame_id)
            else:
                self._pending.discard(frame_id)
            if not people and not scene.pending and not scene.tracker.groups:
                del self._frames[frame_id]  # nobody left: forget the frame (memory bound)
                self._due.pop(frame_id, None)
                self._past[frame_id] = scene.stamp
                self._past.move_to_end(frame_id)
                if len(self._past) > self.PAST_FRAMES:
                    self._past.popitem(last=False)
            else:
                self._past.pop(frame_id, None)
        return out

    def current(self) -> list[SceneUpdate]:
        """Every frame's scene as last said (for queries)."""
        return [scene.snapshot() for scene in self._frames.values() if scene.said_once]

    def empty(self, frame_id: str) -> SceneUpdate | None:
        """The scene of a frame known to this service with nobody in it now (no group, no
        pair, at its last stamp); None for a frame never seen or forgotten."""
        if frame_id in self._frames or frame_id in self._dirty:
            stamp = self._frames[frame_id].stamp if frame_id in self._frames else ZERO
        elif frame_id in self._past:
            stamp = self._past[frame_id]
        else:
            return None
        return nobody(frame_id, stamp)


def nobody(frame_id: str, stamp: Time) -> SceneUpdate:
    """A frame's scene with nobody in it: no group, no pair."""
    return SceneUpdate(frame_id, stamp, (), (), (), frozenset(), False, False, 0, ())
