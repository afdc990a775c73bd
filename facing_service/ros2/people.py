"""People of a ROS4HRI robot, from its TF tree and tracked lists, as the tracker's samples.

Pure: messages in (as plain values), pose samples and losses out. The rules:

- The tracked lists define who exists: ``/humans/bodies/tracked``, ``/humans/faces/tracked``
  and ``/humans/persons/tracked``. An id that leaves its list is lost at once.
- One human is one subject, a participant (``participants.derive``: a tracked person,
  and each face or body no tracked person holds), named ``<kind>_<id>`` (``body_1f3a``,
  ``face_959e0``, ``person_rorql``: REP 155's frame names, a person by its id), derived
  whole from the current lists and links whenever they change: nothing outlives the
  link that made it. A face or body that becomes a person's is lost as a subject; one no
  person holds comes back.
- A person's pose is where it looks (its face, else its body; a frame that cannot be
  looked up yet gives way to the next), with its ``stance`` (its tracked body apart, at
  the same time); a body's or face's is its own frame (x forward).
- Each pose is tf2's lookup of that frame in the base frame at the latest common time,
  redone whenever a transform on its chain (or the base frame's) changes; a pose is
  emitted only when that time moves forward, so nothing already said is repeated.
- A face or body that no person holds waits ``join_wait_ns`` of its own stamps before its
  first results (``--ros-join-wait-s``): a person manager links a new face or body a
  moment after its tracker lists it, and through another subscription.
- First results are delayed, never lost: the lists and person links come through other
  subscriptions than /tf and may be handled after /tf that came after them (as may a
  /tf_static link), so when a subject's pose first becomes known, the poses its frame
  already holds from the last ``FIRST_RESULTS_NS`` are said first, oldest first (at most
  ``MAX_FIRST_RESULTS``), each looked up at its own stamp.
- Bounded, whatever the robot sends: at most ``max_ids`` ids per list (the first kept,
  the others refused as ``capacity``), at most ``max_ids`` person links of each kind
  (those of untracked persons are kept for when they come, and the oldest forgotten
  first), and the TF buffer's ``max_frames``.
- Time going back (a recording replayed again, a robot's clock reset; told as
  ``time_back`` says): the dynamic transforms are cleared and every subject is lost,
  then comes back with the new times. The /tf messages that went back are held meanwhile
  (at most ``MAX_HELD_BACK``), the new timeline's first once it is told.
- Links cannot amplify: a face or body frame is the pose of at most one person at a time
  (the one that linked it last), so 200 cloned person ids pointing at a real face make
  one stream of results, never 200. Frame names are bounded (``MAX_FRAME_NAME``,
  ``tf_frame_name_too_long``).
- Nothing is emitted twice: a subject lost and back (a person leaving its list for one
  message, a face no longer a person's) resumes after the last stamp emitted for it
  (``_emitted_before``, bounded), so the tracker never refuses its first results as out of
  order.
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
from .participants import PERSONS, Participant, Presence, derive
from .time_back import TimeBack

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

MAX_HELD_BACK = 64  # /tf messages held while time going back is told (a burst: refused)
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


def harmless(refused: str) -> bool:
    """Whether a refusal (its ``what``) is one the message itself calls harmless."""
    return refused.endswith(STATIC_INTO_DYNAMIC)


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
        join_wait_ns: int = 0,
    ) -> None:
        self.base_frame = base_frame
        self.max_ids = max_ids
        self.join_wait_ns = join_wait_ns
        # a face or body nobody holds, not emitted yet -> the first stamp it could be
        self._waiting: dict[str, int] = {}
        self.tf = TfBuffer(max_frames=max_frames)
        self._tracked: dict[str, set[str]] = {topic: set() for topic in KINDS}
        # person -> the id it links, per kind; oldest link first (the last one made wins)
        self._links: dict[str, dict[str, str]] = {"face_": {}, "body_": {}}
        # participant -> the stamp of the last pose emitted, and the frame it was read from
        self._last: dict[str, tuple[int, str]] = {}
        # a subject no longer a participant -> the last stamp emitted for it (oldest first)
        self._emitted_before: dict[str, int] = {}
        # Derived whole from the lists and links, when they change (see participants)
        self.presence: Presence = derive(self._tracked, self._links)
        self._time_back = TimeBack()
        # its messages, held: the new timeline's first once time went back, else refused
        self._held_back: list[Sequence[TfInput]] = []
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
        messages: list[Sequence[TfInput]] = [transforms]
        if not static:
            stamps = ((t.stamp, self.tf.newest(t.child)) for t in transforms)
            back = self._time_back.observe(stamps, publisher, received_s)
            if back:
                update.time_back_ns = back
                update.lost = [s for s in self.subjects() if s in self._last]
                self.tf.clear()
                self._last.clear()
                self._emitted_before.clear()  # older stamps are the new timeline
                self._waiting.clear()
            elif self._time_back.under_way and len(self._held_back) < MAX_HELD_BACK:
                self._held_back.append(transforms)  # evidence under way: not refused yet
                return update
            messages, self._held_back = [*self._held_back, transforms], []
        changed: set[str] = set()
        for t in (t for message in messages for t in message):
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
        frames = set().union(*(self.tf.descendants(frame) for frame in changed))
        by_frame = self.presence.by_frame
        return sorted({s for frame in frames for s in by_frame.get(frame, ())})

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
        if valid != current:
            self._tracked[topic] = valid
            self._derive(update)
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
        links.pop(person_id, None)  # (re)inserted last: the newest link, forgotten last
        if target:
            links[person_id] = target
            self._forget_links(links, link, update)
        if person_id in self._tracked[PERSONS]:  # (an untracked person's links hold nothing)
            self._derive(update)
        return update

    def _derive(self, update: Update) -> None:
        """Who is there, derived again after a list or a link changed: a participant no
        longer there, or with no frame left to read (a person that links nothing), is
        lost once emitted, and one new or reading other frames is resolved (its first
        results emitted, after what was emitted for it before)."""
        before, self.presence = self.presence, derive(self._tracked, self._links)
        now = self.presence.participants
        self._waiting = {s: t for s, t in self._waiting.items() if s in now}
        changed = [s for s, p in now.items() if before.participants.get(s) != p]
        self._resolve(changed, update)
        # lost: no longer there, or no longer reading the frame it was read from with
        # none it may read now that can be looked up (a person that links nothing)
        for subject, (stamp, frame) in sorted(self._last.items()):
            if subject not in now or (
                frame not in now[subject].looks and self._look_up(now[subject], Update()) is None
            ):
                del self._last[subject]
                update.lost.append(subject)
                self._emitted_before.pop(subject, None)
                self._emitted_before[subject] = stamp
                while len(self._emitted_before) > self.max_ids:
                    del self._emitted_before[next(iter(self._emitted_before))]

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

    @property
    def clears(self) -> int:
        """TF buffer clears: time went back."""
        return self._time_back.clears

    @property
    def clears_refused(self) -> int:
        """Clears not made: time went back again too soon after the last."""
        return self._time_back.clears_refused

    def subjects(self) -> list[str]:
        """Every participant tracked, by our name: each tracked person, and each tracked
        face or body that no tracked person holds (those that one does are its)."""
        return sorted(self.presence.participants)

    def frame_of(self, subject: str) -> str | None:
        """The TF frame a subject's pose (where it looks) is read from first, or None
        when it has none."""
        participant = self.presence.participants.get(subject)
        if participant is None:  # (not a participant now: its own frame, if a face or body)
            return None if subject.startswith("person_") else subject
        return next(iter(participant.looks), None)

    def _resolve(self, subjects: Iterable[str], update: Update) -> None:
        for subject in subjects:
            participant = self.presence.participants.get(subject)
            if participant is None:
                continue
            looked_up = self._look_up(participant, update)
            if looked_up is None:
                continue
            frame, transform, stamp = looked_up
            emitted = self._last.get(subject)
            if emitted is not None and (stamp < emitted[0] or (stamp, frame) == emitted):
                continue  # nothing newer than what was already emitted (another frame at
                # the same time is: the tracker takes an equal stamp)
            stands = participant.stands if participant.stands != frame else None
            if emitted is None and self._waits(subject, stamp):
                continue
            if emitted is None:  # first known: what its frame already holds, emitted first
                before = self._emitted_before.get(subject)
                if before is not None and stamp <= before:
                    continue  # emitted already, before it was lost
                self._emitted_before.pop(subject, None)
                self._first_results(subject, frame, stands, stamp, before, update)
            self._last[subject] = (stamp, frame)
            update.poses.append(self._sample(subject, frame, stands, transform, stamp))

    def _waits(self, subject: str, stamp: int) -> bool:
        """Whether a face or body that no person holds waits before its first results,
        ``join_wait_ns`` of its stamps (then emitted from its first): a person manager
        links a new face after the face tracker lists it, and the face emitted meanwhile
        as a participant of its own would be a double, lost a moment later."""
        if not self.join_wait_ns or subject.startswith("person_"):
            return False
        first = self._waiting.setdefault(subject, stamp)
        if stamp - first < self.join_wait_ns:
            return True
        del self._waiting[subject]
        return False

    def _look_up(
        self, participant: Participant, update: Update
    ) -> tuple[str, RigidTransform, int] | None:
        """Where a participant looks from now: the first of its frames that can be looked
        up in the base frame (a face under a camera not yet connected gives way to the
        body), with its transform at the latest common time."""
        tried = False
        for frame in participant.looks:
            if not self.tf.has_frame(frame):
                continue
            try:
                transform, stamp = self.tf.lookup(self.base_frame, frame, 0)
            except TfError:
                tried = True
                continue
            return frame, transform, stamp
        if tried:
            update.unresolved += 1
        return None

    def _stance(self, frame: str | None, stamp: int) -> Stance | None:
        """Where a person stands at ``stamp``: in its body ``frame`` (at that time, else its
        latest), or None when it has no body apart or it cannot be looked up yet."""
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

    def _first_results(
        self, subject: str, frame: str, stands: str | None, upto: int, after: int | None,
        update: Update,
    ) -> None:  # fmt: skip
        """The subject's poses before ``upto`` (and after ``after``, the last emitted for it
        before) that its frame holds, each standing in ``stands`` (see the module's rules);
        a stamp that cannot be looked up (another link has no data then) is skipped."""
        since = (
            upto - FIRST_RESULTS_NS if after is None else max(upto - FIRST_RESULTS_NS, after + 1)
        )
        for stamp in self.tf.stamps(frame, since, upto - 1)[-MAX_FIRST_RESULTS:]:
            try:
                transform, _ = self.tf.lookup(self.base_frame, frame, stamp)
            except TfError:
                continue
            update.poses.append(self._sample(subject, frame, stands, transform, stamp))

    def _sample(
        self, subject: str, frame: str, stands: str | None, transform: RigidTransform,
        stamp: int,
    ) -> PoseSample:  # fmt: skip
        profile = "head" if frame.startswith("face_") else "body"
        pose = _pose(transform, stamp)
        if (stance := self._stance(stands, stamp)) is not None:
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
