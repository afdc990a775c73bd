"""A TF buffer that answers like tf2's BufferCore: pure, no I/O, no ROS.

The rules kept (tf2 ``buffer_core.cpp`` / ``cache.cpp``, as in ROS 2 Humble and ROS 1 noetic,
whose ``tf2_py`` is the differential test's oracle):

- one parent per child at a time; a frame's cache is static or dynamic as its *first*
  transform was, for good (a later transform of the other kind goes into the same cache:
  a static cache then simply holds the newest one);
- a static transform is valid at every time;
- a dynamic frame keeps ``cache_time`` (10 s) of history, pruned relative to that frame's
  newest stamp; data older than that is refused (``old_data``), a repeated stamp too
  (``repeated_data``);
- lookups interpolate between the two stamps around the time (translation lerp, rotation
  slerp, tf2's own formulas: quaternions are used as given, not renormalized), and a
  lookup at time 0 is at the latest time common to every dynamic link of the chain;
- input checks: NaN (``nan``), ``abs(|q|^2 - 1) >= 0.01`` (``denormalized_quaternion``),
  child equal to parent (``self_transform``), empty ids (``no_child_frame_id``,
  ``no_frame_id``); each one refuses the transform with a reason, never raises;
- lookup errors are tf2's four kinds, with tf2's messages.

Times are integer nanoseconds, as ROS 2's ``TimePoint``.
"""

from __future__ import annotations

import math

from ...contract.robot import DEFAULT_MAX_FRAMES
from .cache import DEFAULT_CACHE_TIME_NS, S_NS, StaticCache, Stored, TimeCache
from .errors import (
    ConnectivityError,
    ExtrapolationError,
    InvalidArgumentError,
    LookupError_,
)
from .geometry import IDENTITY, Quat, RigidTransform, Vec, add, neg, qinv, qmul, rotate

QUATERNION_NORMALIZATION_TOLERANCE = 10e-3
MAX_GRAPH_DEPTH = 1000


# -- tf2's LinearMath, as it computes (no renormalization anywhere) ---------------------


# -- caches -------------------------------------------------------------------------------


# -- the buffer -----------------------------------------------------------------------------


def check_transform(parent: str, child: str, transform: RigidTransform) -> str | None:
    """tf2's input checks: the reason a transform is refused, or None."""
    if child == parent:
        return "self_transform"
    if not child:
        return "no_child_frame_id"
    if not parent:
        return "no_frame_id"
    if not all(map(math.isfinite, (*transform.translation, *transform.rotation))):
        return "nan"  # tf2 lets infinities through to poison lookups; we refuse them alike
    x, y, z, w = transform.rotation
    norm2 = x * x + y * y + z * z + w * w
    if not abs(norm2 - 1.0) < QUATERNION_NORMALIZATION_TOLERANCE:
        return "denormalized_quaternion"
    return None


class TfBuffer:
    """Transforms by child frame; ``set_transform`` and ``lookup`` as tf2's BufferCore.

    Unlike tf2, it names at most ``max_frames`` frames: a transform that would name more
    is refused (``too_many_frames``) unless frames that are gone can be forgotten first,
    dynamic leaves with nothing newer than ``cache_time`` before the buffer's newest
    stamp (a person who left). The sweep runs at most once per second of stamps, so a
    robot that keeps naming new frames costs one pass over them a second, not one each."""

    def __init__(
        self, cache_time_ns: int = DEFAULT_CACHE_TIME_NS, max_frames: int = DEFAULT_MAX_FRAMES
    ) -> None:
        self.cache_time_ns = cache_time_ns
        self.max_frames = max_frames
        self._caches: dict[str, StaticCache | TimeCache] = {}
        self._frames: set[str] = set()  # every frame named so far, as child or parent
        self._children: dict[str, set[str]] = {}  # by each child's latest parent
        self._newest = 0  # the newest stamp stored, of any frame
        self._swept = -cache_time_ns  # ``_newest`` at the last sweep for gone frames
        #: Counts changes of the tree's shape (a frame's latest parent, frames forgotten):
        #: what a caller's cache of chains is keyed on.
        self.shape = 0

    def set_transform(
        self, parent: str, child: str, stamp_ns: int, transform: RigidTransform, *, static: bool
    ) -> str | None:
        """Store a transform; returns None, or the reason tf2 would refuse it (or
        ``too_many_frames``)."""
        if reason := check_transform(parent, child, transform):
            return reason
        new = (child not in self._frames) + (parent not in self._frames)
        if new and len(self._frames) + new > self.max_frames and not self._forget_gone(new):
            return "too_many_frames"
        if not static:
            self._newest = max(self._newest, stamp_ns)
        cache = self._caches.get(child)
        if cache is None:
            cache = StaticCache() if static else TimeCache(self.cache_time_ns)
            self._caches[child] = cache
        self._frames.update((child, parent))
        before = cache.latest()[1]
        refused = cache.insert(Stored(stamp_ns, parent, transform))
        after = cache.latest()[1]
        if after != before:
            self.shape += 1
            if before is not None:
                self._children[before].discard(child)
            self._children.setdefault(after, set()).add(child)  # type: ignore[arg-type]
        return refused

    def has_frame(self, frame: str) -> bool:
        return frame in self._frames

    def _forget_gone(self, room: int) -> bool:
        """Forget dynamic leaf frames silent for ``cache_time`` (and roots left with no
        child); whether ``room`` more frames now fit. At most one sweep per second of
        stamps."""
        if self._newest - self._swept < S_NS:
            return False
        self._swept = self._newest
        horizon = self._newest - self.cache_time_ns
        for frame, cache in list(self._caches.items()):
            if cache.is_static or self._children.get(frame) or cache.latest()[0] >= horizon:
                continue
            parent = cache.latest()[1]
            del self._caches[frame]
            self.shape += 1
            self._frames.discard(frame)
            self._children.pop(frame, None)
            siblings = self._children.get(parent)  # type: ignore[arg-type]
            if siblings is not None:
                siblings.discard(frame)
                if not siblings and parent not in self._caches:  # a root left alone
                    del self._children[parent]  # type: ignore[arg-type]
                    self._frames.discard(parent)
        return len(self._frames) + room <= self.max_frames

    def stamps(self, frame: str, after: int, upto: int) -> list[int]:
        """The stamps of ``frame``'s own transforms in ``(after, upto]``, oldest first
        (none for a static frame)."""
        cache = self._caches.get(frame)
        return cache.stamps(after, upto) if isinstance(cache, TimeCache) else []

    def clear(self) -> None:
        """Forget every dynamic transform, keep the static ones: tf2's ``BufferCore::clear``
        (a static cache's ``clearList`` keeps its transform), which ROS's TF listener calls
        when time jumps back."""
        static = {c: cache for c, cache in self._caches.items() if cache.is_static}
        self._caches, self._frames, self._children = {}, set(), {}
        self._newest, self._swept = 0, -self.cache_time_ns
        self.shape += 1
        for child, cache in static.items():
            self._caches[child] = cache
            parent = cache.latest()[1]
            assert parent is not None  # a cache exists once it holds a transform
            self._frames.update((child, parent))
            self._children.setdefault(parent, set()).add(child)

    def newest(self, frame: str) -> int | None:
        """The newest stamp of ``frame``'s own transform (None: static, or no transform)."""
        cache = self._caches.get(frame)
        return None if cache is None or cache.is_static else cache.latest()[0]

    def frames(self) -> set[str]:
        """Every frame named so far, as a child or a parent."""
        return set(self._frames)

    def roots(self) -> list[str]:
        """The frames with no parent: one per tree (tf2's view_frames draws them on top)."""
        return sorted(self._frames - self._caches.keys())

    def root_of(self, frame: str) -> str:
        """The top of ``frame``'s tree by latest parents (a frame in a loop: where it loops)."""
        return self.parent_chain(frame)[-1]

    def descendants(self, frame: str) -> set[str]:
        """``frame`` and every frame below it, by latest parents: whose lookups a change of
        ``frame``'s transform can change."""
        found, todo = {frame}, [frame]
        while todo:
            for child in self._children.get(todo.pop(), ()):
                if child not in found:
                    found.add(child)
                    todo.append(child)
        return found

    def parent_chain(self, frame: str) -> list[str]:
        """``frame`` and its ancestors by their latest parents (for "does a change of X
        concern a lookup of Y"), stopping at a root or a loop."""
        chain = [frame]
        while (cache := self._caches.get(chain[-1])) is not None:
            parent = cache.latest()[1]
            if parent is None or parent in chain or len(chain) > MAX_GRAPH_DEPTH:
                break
            chain.append(parent)
        return chain

    # -- lookups -------------------------------------------------------------------------

    def _validate(self, frame: str, argument: str) -> None:
        if frame in self._frames and frame[0] != "/":  # the usual case, first
            return
        if not frame:
            raise InvalidArgumentError(
                f"Invalid argument passed to lookupTransform argument {argument} in tf2 "
                "frame_ids cannot be empty"
            )
        if frame.startswith("/"):
            raise InvalidArgumentError(
                f'Invalid argument "{frame}" passed to lookupTransform argument {argument} in '
                "tf2 frame_ids cannot start with a '/' like: "
            )
        if frame not in self._frames:
            raise LookupError_(
                f'"{frame}" passed to lookupTransform argument {argument} does not exist. '
            )

    def lookup(self, target: str, source: str, time_ns: int = 0) -> tuple[RigidTransform, int]:
        """The pose of ``source`` in ``target`` at ``time_ns`` (0: the latest common time),
        and the time it is for. Raises TfError as tf2 would."""
        if target == source:
            if time_ns == 0 and (cache := self._caches.get(target)) is not None:
                time_ns = cache.latest()[0]
            return IDENTITY, time_ns
        self._validate(target, "target_frame")
        self._validate(source, "source_frame")
        if time_ns == 0:
            time_ns = self.latest_common_time(target, source)
        return self._walk(target, source, time_ns), time_ns

    def _gather(self, frame: str, time: int) -> Stored | None:
        cache = self._caches.get(frame)
        return None if cache is None else cache.get(time)

    def _walk(self, target: str, source: str, time: int) -> RigidTransform:
        """tf2's ``walkToTopParent`` with its ``TransformAccum``."""
        src_vec: Vec = (0.0, 0.0, 0.0)
        src_quat: Quat = (0.0, 0.0, 0.0, 1.0)
        frame, top_parent, depth = source, source, 0
        extrapolation: ExtrapolationError | None = None
        while True:
            if frame not in self._caches:
                top_parent = frame
                break
            try:
                stored = self._gather(frame, time)
            except ExtrapolationError as error:
                extrapolation, top_parent = error, frame
                break
            assert stored is not None
            if frame == target:  # the target is an ancestor of the source
                return RigidTransform(src_vec, src_quat)
            t = stored.transform
            src_vec = add(rotate(t.rotation, src_vec), t.translation)
            src_quat = qmul(t.rotation, src_quat)
            top_parent, frame = frame, stored.parent
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                raise LookupError_("The tf tree is invalid because it contains a loop.")
        tgt_vec: Vec = (0.0, 0.0, 0.0)
        tgt_quat: Quat = (0.0, 0.0, 0.0, 1.0)
        frame, depth = target, 0
        while frame != top_parent:
            if frame not in self._caches:
                break
            try:
                stored = self._gather(frame, time)
            except ExtrapolationError as error:
                raise ExtrapolationError(
                    f"{error}, when looking up transform from frame [{source}] to frame [{target}]"
                ) from None
            assert stored is not None
            if frame == source:  # the source is an ancestor of the target
                inv = qinv(tgt_quat)
                return RigidTransform(rotate(inv, neg(tgt_vec)), inv)
            t = stored.transform
            tgt_vec = add(rotate(t.rotation, tgt_vec), t.translation)
            tgt_quat = qmul(t.rotation, tgt_quat)
            frame = stored.parent
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                raise LookupError_("The tf tree is invalid because it contains a loop.")
        if frame != top_parent:
            if extrapolation is not None:
                raise ExtrapolationError(
                    f"{extrapolation}, when looking up transform from frame [{source}] to "
                    f"frame [{target}]"
                )
            raise _disconnected(target, source)
        inv = qinv(tgt_quat)
        return RigidTransform(
            add(rotate(inv, src_vec), rotate(inv, neg(tgt_vec))), qmul(inv, src_quat)
        )

    def _latest_link(self, frame: str) -> tuple[int, str] | None:
        """``(latest stamp, parent)`` of ``frame`` (stamp 0 when static); None at a root."""
        cache = self._caches.get(frame)
        if cache is None:
            return None
        stamp, parent = cache.latest()
        return None if parent is None else (stamp, parent)

    def latest_common_time(self, target: str, source: str) -> int:
        """tf2's ``getLatestCommonTime``: the newest time every dynamic link between the two
        frames has data for (0 when the chain is all static)."""
        if source == target:
            cache = self._caches.get(source)
            return cache.latest()[0] if cache else 0
        never = math.inf
        common: float = never
        seen: list[tuple[int, str]] = []  # (latest stamp, parent) walking up from the source
        seen_parents: set[str] = set()  # the same parents, to look up in O(1)
        frame, depth = source, 0
        while (link := self._latest_link(frame)) is not None:
            stamp, parent = link
            if stamp:
                common = min(common, stamp)
            seen.append((stamp, parent))
            seen_parents.add(parent)
            frame = parent
            if frame == target:
                return 0 if common == never else int(common)
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                raise LookupError_("The tf tree is invalid because it contains a loop.")
        frame, depth, common = target, 0, never
        common_parent: str | None = None
        while (link := self._latest_link(frame)) is not None:
            stamp, parent = link
            if stamp:
                common = min(common, stamp)
            if parent in seen_parents:
                common_parent = parent
                break
            frame = parent
            if frame == source:
                return 0 if common == never else int(common)
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                raise LookupError_("The tf tree is invalid because it contains a loop.")
        if common_parent is None:
            raise _disconnected(target, source)
        for stamp, parent in seen:
            if stamp:
                common = min(common, stamp)
            if parent == common_parent:
                break
        return 0 if common == never else int(common)


def _disconnected(target: str, source: str) -> ConnectivityError:
    return ConnectivityError(
        f"Could not find a connection between '{target}' and '{source}' because they are not "
        "part of the same tree.Tf has two or more unconnected trees."
    )
