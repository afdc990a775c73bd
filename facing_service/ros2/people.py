"""People of a ROS4HRI robot, from its TF tree and tracked lists, as the tracker's samples.

Pure: messages in (as plain values), pose samples and losses out. The rules:

- The tracked lists define who exists: ``/humans/bodies/tracked``, ``/humans/faces/tracked``
  and ``/humans/persons/tracked``. An id that leaves its list is lost at once.
- One human is one subject, a participant (``participants``: a tracked person, and each
  face or body no tracked person links), named ``<kind>_<id>`` (``body_1f3a``,
  ``face_959e0``, ``person_rorql``: REP 155's frame names, a person by its id). A face or
  body that becomes a person's is lost as a subject; one no person links comes back.
- A person's pose is where it looks (its face, else its body), with its ``stance`` (its
  body apart, at the same time); a body's or face's is its own frame (x forward).
- Each pose is tf2's lookup of that frame in the base frame at the latest common time,
  redone whenever a transform on its chain (or the base frame's) changes; a pose is
  emitted only when that time moves forward, so nothing already said is repeated.
- First results are delayed, never lost: the lists and person links come through other
  subscriptions than /tf and may be handled after /tf that came after them (as may a
  /tf_static link), so when a subject's pose first becomes known, the poses its frame
  already holds from the last ``FIRST_RESULTS_NS`` are said first, oldest first (at most
  ``MAX_FIRST_RESULTS``), each looked up at its own stamp.
- Bounded, whatever the robot sends: at most ``max_ids`` ids per list (the first kept,
  the others refused as ``capacity``), at most ``max_ids`` person links of each kind
  (those of untracked persons are kept for when they come, and the oldest forgotten
  first), and the TF buffer's ``max_frames``.
- Time going back (a recording replayed again, a robot's clock reset): ROS's TF listener
  clears its buffer when its clock jumps back. Here the clock is the stamps: after
  ``TIME_BACK_MESSAGES`` /tf messages in a row *from one publisher* (rmw_zenoh's GID, when
  the caller knows it), spanning at least ``TIME_BACK_SPAN_S`` of receive time, whose every
  transform is more than ``TIME_BACK_NS`` older than its frame's newest, the dynamic
  transforms are cleared and every subject is lost, then comes back with the new times.
  In a row: a stale or forged message between fresh ones clears nothing, and a burst of
  forged ones cannot span the time while the robot streams. Clears are counted, and at
  most one in ``CLEAR_MIN_INTERVAL_S`` (the others are counted as refused).
- Links cannot amplify: a face or body frame is the pose of at most one person at a time,
  the first tracked person to resolve it, until that person is lost or relinked; another
  person linked to it gets no pose (``link_taken``, counted once per link), so 200 cloned
  person ids pointing at a real face make no results, and the face is that first person's
  alone. Frame names are bounded
  (``MAX_FRAME_NAME``, ``tf_frame_name_too_long``).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

from ..contract import keys
from ..contract.poses import MAX_TRANSLATION_M, Pose, Stance
from ..contract.robot import DEFAULT_MAX_FRAMES
from ..contract.stamps import NS_PER_S, Time
from ..core.records import PoseSample
from ..core.tf.buffer import TfBuffer
from ..core.tf.errors import TfError
from ..core.tf.geometry import RigidTransform
from .participants import PERSONS, aliases, look_frame, stance_frame

#: tracked list topic -> (our subject prefix, the TF frame prefix of REP 155)
KINDS = {
    "/humans/bodies/tracked": ("body_", "body_"),
    "/humans/faces/tracked": ("face_", "face_"),
    "/humans/persons/tracked": ("person_", None),
}
PERSON_LINKS = {"face_id": "face_", "body_id": "body_"}

#: When a subject's pose first becomes known: how far back its frame's poses are said too,
#: and at most how many (a tracker's list handled 0.2-1 s after the /tf that came with it,
#: under load, lost those results; 64 covers 2 s at 30 Hz).
FIRST_RESULTS_NS = 2 * NS_PER_S
MAX_FIRST_RESULTS = 64
#: Ids per list and person links per kind, unless the caller says (``--max-bodies``).
DEFAULT_MAX_IDS = 10_000

#: How far back a transform's stamp must be, for how many /tf messages in a row from one
#: publisher, over how much receive time, for time to have gone back (a stream at 30 Hz
#: says so within a third of a second).
TIME_BACK_NS = NS_PER_S // 2
TIME_BACK_MESSAGES = 3
TIME_BACK_SPAN_S = 0.25
#: At most one TF buffer clear in this long (a replay looping every few seconds is still
#: followed; a flood of forged rewinds is not).
CLEAR_MIN_INTERVAL_S = 2.0
#: Longest frame name kept (ROS names have no limit; tf2 keeps every one it sees).
MAX_FRAME_NAME = 256
#: Said with a /tf_static transform refused because its frame is dynamic: seen on the
#: shared two-person recordings (a camera frame with a static and a dynamic parent, the
#: /tf one first), harmless there, and alarming without a word.
STATIC_INTO_DYNAMIC = (
    " (a /tf_static transform of a frame first seen on /tf: tf2 keeps a frame static or "
    "dynamic as its first transform was, so this one is refused; harmless when the /tf "
    "parent is the one meant)"
)


def _name_too_long(t: TfInput) -> str | None:
    """Frame names are sender-chosen and tf2 keeps every one: bounded here."""
    if len(t.parent) > MAX_FRAME_NAME or len(t.child) > MAX_FRAME_NAME:
        return "frame_name_too_long"
    return None


def out_of_range(t: TfInput) -> str | None:
    """Why a transform carries numbers our outputs cannot (checked before tf2's own rules):
    a stamp outside builtin_interfaces/Time's range, or a translation beyond the JSON
    contract's bound. With every link bounded, every composed lookup is finite."""
    if t.stamp is None:
        return "invalid_stamp"
    if any(math.isfinite(v) and abs(v) > MAX_TRANSLATION_M for v in t.transform.translation):
        return "out_of_range"  # (non-finite values are tf2's own check: nan)
    return None


@dataclass(frozen=True, slots=True)
class TfInput:
    parent: str
    child: str
    stamp: Time | None  # None: outside builtin_interfaces/Time's range (refused)
    transform: RigidTransform


@dataclass
class Update:
    """What one input changed: poses for the tracker, subjects lost, inputs refused."""

    poses: list[PoseSample] = field(default_factory=list)
    lost: list[str] = field(default_factory=list)
    refused: list[tuple[str, str]] = field(default_factory=list)  # (reason, what)
    unresolved: int = 0  # lookups not possible yet (frame unknown, no common time...)
    time_back_ns: int = 0  # time went back this far: the buffer was cleared


class People:
    """The robot's people, as seen in ``base_frame``."""

    def __init__(
        self,
        base_frame: str,
        *,
        max_ids: int = DEFAULT_MAX_IDS,
        max_frames: int = DEFAULT_MAX_FRAMES,
    ) -> None:
        self.base_frame = base_frame
        self.max_ids = max_ids
        self.tf = TfBuffer(max_frames=max_frames)
        self._tracked: dict[str, set[str]] = {topic: set() for topic in KINDS}
        self._links: dict[str, dict[str, str]] = {"face_": {}, "body_": {}}  # person -> id
        self._last: dict[str, int] = {}  # subject -> stamp of the last pose emitted
        self._owner: dict[str, str] = {}  # frame -> the person subject whose pose it is
        self._aliases: dict[str, str] = {}  # face or body subject -> the person it is
        self._taken: set[str] = set()  # person subjects refused as link_taken (said once)
        self._by_frame: dict[str, set[str]] | None = None  # frame -> subjects; None: stale
        # /tf messages whose every transform went back in time: (publisher, count, since)
        self._back_run: tuple[bytes | None, int, float | None] = (None, 0, None)
        self._last_clear: float | None = None  # receive time of the last buffer clear
        self.clears = 0  # TF buffer clears (time went back)
        self.clears_refused = 0  # clears not made: within CLEAR_MIN_INTERVAL_S of the last
        self._base_chain: tuple[int, frozenset[str]] = (-1, frozenset())  # (tf.shape, chain)

    # -- inputs --------------------------------------------------------------------------

    def on_tf(
        self,
        transforms: Sequence[TfInput],
        *,
        static: bool,
        publisher: bytes | None = None,
        received_s: float | None = None,
    ) -> Update:
        """A /tf or /tf_static message from ``publisher`` (its GID, None when unknown),
        received at ``received_s`` (the caller's clock; None: judge by messages alone)."""
        update = Update()
        if not static and (back := self._time_back(transforms, publisher, received_s)):
            update.time_back_ns = back
            update.lost = [s for s in self.subjects() if s in self._last]
            self.tf.clear()
            self._last.clear()
        changed: set[str] = set()
        for t in transforms:
            reason = out_of_range(t) or _name_too_long(t)
            if reason is None and t.stamp is not None:
                reason = self.tf.set_transform(
                    t.parent, t.child, t.stamp, t.transform, static=static
                )
            if reason is None:
                changed.add(t.child)
            else:
                what = f"{keys.cut(t.parent)} -> {keys.cut(t.child)}"
                if static and self.tf.newest(t.child) is not None:  # a dynamic frame
                    what += STATIC_INTO_DYNAMIC
                update.refused.append((f"tf_{reason}", what))
        if changed:
            self._resolve(self._concerned(changed), update)
        return update

    def _time_back(
        self, transforms: Sequence[TfInput], publisher: bytes | None, received_s: float | None
    ) -> int:
        """How far back time went, once it has (see the module's rules; 0: it has not)."""
        back = []
        for t in transforms:
            if t.stamp is None:
                continue  # no time at all: refused, and no sign of time going back
            newest = self.tf.newest(t.child)
            if newest is None or t.stamp >= newest - TIME_BACK_NS:
                self._back_run = (None, 0, None)  # a fresh (or first) transform: time goes on
                return 0
            back.append(newest - t.stamp)
        if not back:
            return 0
        who, count, since = self._back_run
        if count == 0 or who != publisher:
            who, count, since = publisher, 0, received_s
        self._back_run = (who, count + 1, since)
        if count + 1 < TIME_BACK_MESSAGES:
            return 0
        if received_s is not None and since is not None:
            if received_s - since < TIME_BACK_SPAN_S:
                return 0  # a burst: not yet a clock that went back
            if (
                self._last_clear is not None
                and received_s - self._last_clear < CLEAR_MIN_INTERVAL_S
            ):
                self.clears_refused += 1
                self._back_run = (None, 0, None)
                return 0
            self._last_clear = received_s
        self._back_run = (None, 0, None)
        self.clears += 1
        return max(back)

    def _concerned(self, changed: set[str]) -> list[str]:
        """The subjects whose lookup a change of these frames can change: all of them when
        the base frame's chain moved, else those whose frame is at or below a changed one
        (an index, not a scan: a robot's /tf is mostly one body per message)."""
        shape, chain = self._base_chain
        if shape != self.tf.shape:  # walked again only when the tree's shape changed
            chain = frozenset(self.tf.parent_chain(self.base_frame))
            self._base_chain = (self.tf.shape, chain)
        if not chain.isdisjoint(changed):
            return self.subjects()
        by_frame = self._subjects_by_frame()
        frames = set().union(*(self.tf.descendants(frame) for frame in changed))
        return sorted({s for frame in frames for s in by_frame.get(frame, ())})

    def _subjects_by_frame(self) -> dict[str, set[str]]:
        if self._by_frame is None:
            self._by_frame = {}
            for subject in self.subjects():
                if (frame := self.frame_of(subject)) is not None:
                    self._by_frame.setdefault(frame, set()).add(subject)
        return self._by_frame

    def on_tracked(self, topic: str, ids: Sequence[str]) -> Update:
        update = Update()
        prefix = KINDS[topic][0]
        valid, current = set(), self._tracked[topic]
        for ros_id in ids:
            if not keys.is_name(prefix + ros_id):
                update.refused.append(("invalid_id", f"{topic}: {keys.cut(ros_id)!r}"))
            else:
                valid.add(ros_id)
        if len(valid) > self.max_ids:  # those tracked already first, then in list order
            kept = [i for i in ids if i in current and i in valid]
            kept += [i for i in ids if i not in current and i in valid]
            update.refused.append(
                ("capacity", f"{topic}: {len(valid)} ids, only the first {self.max_ids} kept")
            )
            valid = set(kept[: self.max_ids])
        gone, new = current - valid, valid - current
        self._tracked[topic] = valid
        if gone or new:
            self._by_frame = None
        for ros_id in sorted(gone):
            subject = prefix + ros_id
            if self._last.pop(subject, None) is not None or subject not in self._aliases:
                update.lost.append(subject)
            self._release(subject)
        self._realias(update)
        self._resolve([prefix + ros_id for ros_id in sorted(new)], update)
        return update

    def on_person_link(self, person_id: str, link: str, target: str) -> Update:
        """``/humans/persons/<person_id>/<link>`` said ``target`` ("" for none)."""
        update = Update()
        links = self._links[PERSON_LINKS[link]]
        if target and not keys.is_name(PERSON_LINKS[link] + target):
            update.refused.append(("invalid_id", f"{person_id}/{link}: {keys.cut(target)!r}"))
            return update
        if links.get(person_id, "") == target:
            return update
        self._release("person_" + person_id)
        links.pop(person_id, None)  # (re)inserted last: the oldest are forgotten first
        if target:
            links[person_id] = target
            self._forget_links(links, link, update)
        self._by_frame = None
        if person_id in self._tracked[PERSONS]:  # (an untracked person's links alias nothing)
            self._realias(update)
            self._resolve(["person_" + person_id], update)
        return update

    def _forget_links(self, links: dict[str, str], link: str, update: Update) -> None:
        """Over ``max_ids`` links of a kind: forget the oldest of untracked persons."""
        tracked = self._tracked[PERSONS]
        while len(links) > self.max_ids:
            oldest = next((p for p in links if p not in tracked), None)
            if oldest is None:
                return  # (cannot happen: at most max_ids persons are tracked)
            del links[oldest]
            update.refused.append(
                ("capacity", f"{oldest}/{link}: forgotten, over {self.max_ids} person links")
            )

    # -- state -----------------------------------------------------------------------------

    def subjects(self) -> list[str]:
        """Every participant tracked, by our name: each tracked person, and each tracked
        face or body that no tracked person links (those that one does are its)."""
        return [
            subject
            for topic, ids in self._tracked.items()
            for i in sorted(ids)
            if (subject := KINDS[topic][0] + i) not in self._aliases
        ]

    def frame_of(self, subject: str) -> str | None:
        """The TF frame a subject's pose (where it looks) is read from, or None when it has
        none (yet)."""
        prefix, _, ros_id = subject.partition("_")
        if prefix != "person":
            return subject  # body_<id> and face_<id> are REP 155's frame names
        return look_frame(ros_id, self._tracked, self._links)

    def _realias(self, update: Update) -> None:
        """Which faces and bodies are a tracked person's, after a list or a link changed: one
        that becomes a person's is lost as a subject of its own (the person goes on); one
        that no longer is comes back as its own."""
        before, self._aliases = self._aliases, aliases(self._tracked, self._links, self._owner)
        if before == self._aliases:
            return
        self._by_frame = None
        for alias in sorted(self._aliases.keys() - before.keys()):
            if self._last.pop(alias, None) is not None:
                update.lost.append(alias)
        own = set(self.subjects())  # no longer a person's, and still tracked: its own again
        self._resolve(sorted(s for s in before.keys() - self._aliases.keys() if s in own), update)

    def _release(self, subject: str) -> None:
        """``subject`` no longer holds a frame (lost, or relinked)."""
        self._taken.discard(subject)
        if (frame := self.frame_of(subject)) is not None and self._owner.get(frame) == subject:
            del self._owner[frame]

    def _holds(self, subject: str, frame: str, update: Update) -> bool:
        """Whether ``subject``'s pose may be read from ``frame``: a person's only while no
        other tracked person holds it."""
        if not subject.startswith("person_"):
            return True
        owner = self._owner.setdefault(frame, subject)
        if owner == subject:
            return True
        if subject not in self._taken:
            self._taken.add(subject)
            update.refused.append(
                ("link_taken", f"{keys.cut(subject)}: {keys.cut(frame)} is {owner}'s")
            )
        return False

    def _resolve(self, subjects: Iterable[str], update: Update) -> None:
        for subject in subjects:
            if subject in self._aliases:
                continue  # a person's face or body: its poses are the person's
            frame = self.frame_of(subject)
            if (
                frame is None
                or not self.tf.has_frame(frame)
                or not self._holds(subject, frame, update)
            ):
                continue
            try:
                transform, stamp = self.tf.lookup(self.base_frame, frame, 0)
            except TfError:
                update.unresolved += 1
                continue
            last = self._last.get(subject)
            if last is not None and stamp <= last:
                continue  # nothing newer than what was already said
            if last is None:  # first known: what its frame already holds, said first
                self._first_results(subject, frame, stamp, update)
            self._last[subject] = stamp
            update.poses.append(self._sample(subject, frame, transform, stamp))

    def _stance(self, subject: str, stamp: int) -> Stance | None:
        """Where a person stands at ``stamp`` (its body, at that time, else its latest), or
        None when it has no body apart or it cannot be looked up yet."""
        prefix, _, ros_id = subject.partition("_")
        frame = stance_frame(ros_id, self._tracked, self._links) if prefix == "person" else None
        if frame is None or not self.tf.has_frame(frame):
            return None
        for at in (stamp, 0):
            try:
                transform, _ = self.tf.lookup(self.base_frame, frame, at)
            except TfError:
                continue
            pose = _pose(transform, stamp)
            return pose.translation, pose.rotation
        return None

    def _first_results(self, subject: str, frame: str, upto: int, update: Update) -> None:
        """The subject's poses before ``upto`` that its frame holds (see the module's rules);
        a stamp that cannot be looked up (another link has no data then) is skipped."""
        stamps = self.tf.stamps(frame, upto - FIRST_RESULTS_NS, upto - 1)
        for stamp in stamps[-MAX_FIRST_RESULTS:]:
            try:
                transform, _ = self.tf.lookup(self.base_frame, frame, stamp)
            except TfError:
                continue
            update.poses.append(self._sample(subject, frame, transform, stamp))

    def _sample(
        self, subject: str, frame: str, transform: RigidTransform, stamp: int
    ) -> PoseSample:
        profile = "head" if frame.startswith("face_") else "body"
        pose = _pose(transform, stamp)
        if (stance := self._stance(subject, stamp)) is not None:
            pose = Pose(pose.stamp, pose.translation, pose.rotation, stance)
        return PoseSample(
            keys.BodyRef(frame_id=self.base_frame, body_id=subject),
            pose,
            profile,
        )


def _pose(transform: RigidTransform, stamp_ns: int) -> Pose:
    """tf2 composes quaternions without renormalizing; the detector wants unit ones."""
    x, y, z, w = transform.rotation
    n = math.sqrt(x * x + y * y + z * z + w * w)
    return Pose(
        Time(stamp_ns),
        transform.translation,
        (x / n, y / n, z / n, w / n),
    )
