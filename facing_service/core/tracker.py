"""State over time: the latest pose and decision per (frame, body), and per-frame sets.

Pure: no I/O, no threads, no clock of its own (``now`` is passed in, monotonic seconds),
so every rule here — order, staleness, hysteresis, aggregate changes — is tested without
a network. The service feeds it batches and publishes what each call returns.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import AbstractContextManager
from dataclasses import replace

from ..contract.keys import BodyRef
from ..contract.levels import Level
from ..contract.poses import Pose
from ..contract.schemas import FrameFacing
from ..contract.stamps import NS_PER_S, Time
from . import detector
from .engagement import EngagementParams, Model, advance, observe
from .journal import Journal, Store
from .records import (
    BodyState,
    Changes,
    EngagementUpdate,
    Frame,
    PoseSample,
    Profile,
    Track,
    Window,
    decide,
    frame_facing,
    through_window,
)

#: How long a deleted body's last stamp is remembered (caller's clock): late poses of it
#: from reordered or replayed traffic arrive within well under this.
TOMBSTONE_S = 30.0
#: A tracker that restarts, reusing its ids, its clock starting over, is told from late or
#: stray poses by evidence: this many poses of a body in a row (no accepted one between),
#: each older than its last accepted one (or its DELETE's) by more than RESTART_GAP_S,
#: each newer than the one before. One stale pose, a replayed one, or reordered traffic
#: (jitter is well under the gap) are refused as out of order, as before.
RESTART_EVIDENCE = 3
RESTART_GAP_S = 1.0


class Tracker:
    """Latest pose and decision per (frame, body).

    Rules: a sample whose stamp is older than the latest accepted one for its (frame, body)
    is refused (equal stamps are accepted: re-sent poses still get an answer); a body
    already facing stays facing while its angle is below ``threshold + hysteresis``; a body
    with no accepted sample for ``stale_after_s`` of the caller's clock is lost; a new body
    beyond ``max_bodies`` (all frames together) is refused until others are lost.

    Memory is bounded by ``max_bodies``: frames other than the declared ones are forgotten
    as soon as their last body is lost (after their empty aggregate is published).

    Transactions: the state lives in journaled stores (``journal.Store``), and the
    service wraps each tracker call and the building of its publications in one, so an
    error while saying a change (a bug, a value no output can carry) never leaves a change
    unsaid: no ghost, no aggregate that disagrees with the results.
    """

    def __init__(
        self,
        threshold_deg: float,
        hysteresis_deg: float,
        stale_after_s: float,
        *,
        max_bodies: int,
        engagement: EngagementParams,
        engagement_period_s: float,
        frames: Iterable[str] = (),
        head: Profile | None = None,
    ) -> None:
        """Every tunable comes from the caller (``config.Settings``, their one source)."""
        self.engagement = engagement
        body = Profile(threshold_deg, hysteresis_deg, False, self.engagement)
        self.profiles = {"body": body, "head": head or body}
        self.engagement_period_s = engagement_period_s
        self.stale_after_s = stale_after_s
        self.max_bodies = max_bodies
        self._journal = journal = Journal(after_roll_back=self._rolled_back)
        # Ordered by last accepted sample, oldest first: expiry pops from the front.
        self._tracks: Store[BodyRef, Track] = Store(journal)
        self._declared = frozenset(frames)
        self._frames: Store[str, Frame] = Store(journal, ((f, Frame()) for f in self._declared))
        # After a DELETE: the last accepted stamp, and when the tombstone expires (the
        # caller's clock). Oldest first; at most max_bodies of them.
        self._tombstones: Store[BodyRef, tuple[Time, float]] = Store(journal)
        # Bodies whose level will change with time alone (DISENGAGING's dwell): when.
        self._due: Store[BodyRef, float] = Store(journal)
        # Evidence of a tracker's clock starting over: the last such pose's stamp, and how
        # many in a row (see RESTART_EVIDENCE). Oldest first; at most max_bodies.
        self._older: Store[BodyRef, tuple[Time, int]] = Store(journal)

    def transaction(self) -> AbstractContextManager[None]:
        """Changes made inside apply whole, or not at all (see ``journal``)."""
        return self._journal.transaction()

    def _rolled_back(self) -> None:
        """Back in the orders expiry relies on: tracks by last sample, tombstones by expiry."""
        for key, _ in sorted(self._tracks.items(), key=lambda kv: kv[1].last_seen):
            self._tracks.move_to_end(key)
        for key, _ in sorted(self._tombstones.items(), key=lambda kv: kv[1][1]):
            self._tombstones.move_to_end(key)

    def __len__(self) -> int:
        return len(self._tracks)

    def ingest(self, samples: Sequence[PoseSample], now: float) -> Changes:
        """Accept a batch of validated poses received at ``now``.

        The batch is split into generations (the k-th sample of each body goes into
        generation k) so that each generation is one vectorized call and a body seen twice
        in a batch is still decided in stamp order, with its own hysteresis.
        """
        changes = Changes()
        newest: dict[BodyRef, Time] = {}
        count: dict[BodyRef, int] = {}
        generations: list[list[PoseSample]] = []
        room = self.max_bodies - len(self._tracks)
        restarted: set[BodyRef] = set()
        for sample in samples:
            key = sample.body
            if key in restarted:  # the rest of a restarted body's poses: its new clock
                changes.restarted.append(sample)
                continue
            last = newest.get(key)
            if last is None and (track := self._tracks.peek(key)) is not None:
                last = track.pose.stamp  # (read only: kept when _store changes it)
            if last is None and (tomb := self._tombstones.get(key)) is not None:
                if sample.pose.stamp <= tomb[0]:  # a late pose of a deleted body
                    if self._clock_restarted(key, sample.pose.stamp, tomb[0]):
                        del self._tombstones[key]
                        restarted.add(key)
                        changes.restarted.append(sample)
                    else:
                        changes.out_of_order.append(sample)
                    continue
                del self._tombstones[key]  # newer than the DELETE: the body is back
            if last is None:  # a new body
                if room <= 0:
                    changes.over_capacity.append(sample)
                    continue
                room -= 1
            elif sample.pose.stamp < last:
                if self._clock_restarted(key, sample.pose.stamp, last):
                    restarted.add(key)
                    changes.restarted.append(sample)
                else:
                    changes.out_of_order.append(sample)
                continue
            if key in self._older:  # an accepted pose ends a run of older ones
                del self._older[key]
            newest[key] = sample.pose.stamp
            k = count.get(key, 0)
            count[key] = k + 1
            if k == len(generations):
                generations.append([])
            generations[k].append(sample)
        self._decide(generations, now, changes)
        return changes

    def _decide(self, generations: list[list[PoseSample]], now: float, changes: Changes) -> None:
        """Each generation decided in one call (per body below SMALL_BATCH, vectorized
        above), then the frames they touched."""
        touched: set[str] = set()
        for generation in generations:
            if len(generation) < detector.SMALL_BATCH:
                self._decide_each(generation, now, changes)
            else:
                self._decide_together(generation, now, changes)
            touched.update(s.frame_id for s in generation)
        changes.frames = self._frame_changes(touched)

    def _clock_restarted(self, key: BodyRef, stamp: Time, last: Time) -> bool:
        """Whether this pose, older than the body's ``last``, completes the evidence that
        its tracker's clock started over (RESTART_EVIDENCE); kept towards it otherwise."""
        if last - stamp <= RESTART_GAP_S * NS_PER_S:  # late, not a new clock
            self._older.pop(key, None)
            return False
        before = self._older.get(key)
        count = before[1] + 1 if before is not None and stamp > before[0] else 1
        if count >= RESTART_EVIDENCE:
            del self._older[key]
            return True
        self._older[key] = (stamp, count)
        self._older.move_to_end(key)
        while len(self._older) > self.max_bodies:
            self._older.popitem(last=False)
        return False

    def _decide_each(self, samples: Sequence[PoseSample], now: float, changes: Changes) -> None:
        """A few bodies: one pass per body on floats (``detector.classify_one``), looking
        each track up once (the robot-scale case: most batches are a few bodies)."""
        tracks, profiles = self._tracks, self.profiles
        for sample in samples:
            track = tracks.get(sample.body)
            p = profiles[sample.profile]
            pose = sample.pose
            t, q, threshold = pose.translation, pose.rotation, p.threshold_deg
            was = track is not None and track.state.facing
            applied = threshold + p.hysteresis_deg if was else threshold
            r, angle, distance, facing = detector.classify_one(t, q, applied, p.cone3d)
            recent: Window = ()
            if p.facing_window_s > 0.0:  # (a call per pose only where there is a window)
                facing, recent = through_window(track, p, pose.stamp, angle, applied)
            # fmt: off
            state = BodyState(sample.body, pose.stamp, facing, angle, distance, r, threshold,
                              t, detector.heading_deg(q))
            # fmt: on
            update = self._store(sample, state, p, now, track, recent)
            if update is not None:
                changes.engagement.append(update)
            changes.results.append(state)

    def _decide_together(self, samples: Sequence[PoseSample], now: float, changes: Changes) -> None:
        """Many bodies: one vectorized core call (``detector.classify``)."""
        profiles = [self.profiles[s.profile] for s in samples]
        thresholds = [
            p.threshold_deg + (p.hysteresis_deg if self._was_facing(s.body) else 0.0)
            for s, p in zip(samples, profiles, strict=True)
        ]
        reported = [p.threshold_deg for p in profiles]
        states = decide(samples, thresholds, profiles, reported)
        together = zip(samples, states, profiles, thresholds, strict=True)
        for sample, state, profile, applied in together:
            track = self._tracks.get(sample.body)
            recent: Window = ()
            if profile.facing_window_s > 0.0:
                facing, recent = through_window(
                    track, profile, state.stamp, state.angle_deg, applied
                )
                state = replace(state, facing=facing)
            update = self._store(sample, state, profile, now, track, recent)
            if update is not None:
                changes.engagement.append(update)
            changes.results.append(state)

    def lose(
        self, bodies: BodyRef | Iterable[BodyRef], now: float, *, time_went_back: bool = False
    ) -> Changes:
        """The tracker said these bodies are gone (an input DELETE, or ids leaving a
        tracked list). Poses of each stamped at or before its last accepted one are
        refused for ``TOMBSTONE_S`` after (a late pose must not bring back a body its
        tracker deleted), unless it is lost because time went back: then older stamps are
        the new timeline. One aggregate per frame for all of them: a list replacing N ids
        costs N DELETEs, not N aggregates of everyone. ``now`` (the clock's time) has no
        default: a tombstone dated 0 on a monotonic clock has expired before it is made."""
        changes = Changes()
        frames = set()
        for key in [bodies] if isinstance(bodies, BodyRef) else bodies:
            if (track := self._tracks.get(key)) is None:
                continue
            if not time_went_back:
                self._tombstones[key] = (track.pose.stamp, now + TOMBSTONE_S)
                self._tombstones.move_to_end(key)
                while len(self._tombstones) > self.max_bodies:
                    self._tombstones.popitem(last=False)
            self._remove(key, changes)
            frames.add(key.frame_id)
        changes.frames = self._frame_changes(frames)
        return changes

    def advance(self, now: float) -> Changes:
        """Level changes that time alone makes (DISENGAGING -> DISENGAGED after its dwell)
        for bodies whose tracker went silent: their engagement clock moves on from their
        last stamp by the caller's elapsed time."""
        changes = Changes()
        for key, due in list(self._due.items()):
            if due > now:
                continue
            del self._due[key]
            track = self._tracks.get(key)
            if track is None or track.engagement.last is None:
                continue
            before = track.engagement.level
            t = track.engagement.last + (now - track.last_seen)
            track.engagement = advance(track.engagement, t, track.profile.engagement)
            if track.engagement.level is not before:
                track.engagement_published = now
                changes.engagement.append(track.engagement_update(before))
        return changes

    def next_due(self) -> float | None:
        """When ``advance`` has something to do (caller's clock), or None."""
        return min(self._due.values(), default=None)

    def timed(
        self, now: float, staleness_s: float | None = None, *, advancing: bool = True
    ) -> Iterator[Callable[[], Changes]]:
        """The calls time alone makes due at ``now``, in order: ``expire``, then
        ``advance`` (unless not ``advancing``: the input is silent, so no level moves with
        time alone). Lazy: whether the second is due is asked once the caller has run
        the first (which may lose bodies that were due). The caller runs each (the
        service in a transaction, with its publications)."""
        if (expiry := self.next_expiry(staleness_s)) is not None and expiry <= now:
            yield lambda: self.expire(now, staleness_s)
        if advancing and (due := self.next_due()) is not None and due <= now:
            yield lambda: self.advance(now)

    def expire(self, now: float, staleness_s: float | None = None) -> Changes:
        """Lose every body with no accepted sample for ``staleness_s`` (by default
        ``stale_after_s``; longer while a silent input's people are held, see
        ``core.silence``) before ``now``, and forget expired tombstones."""
        while self._tombstones and next(iter(self._tombstones.values()))[1] <= now:
            self._tombstones.popitem(last=False)
        changes = Changes()
        deadline = now - (self.stale_after_s if staleness_s is None else staleness_s)
        while self._tracks:
            key, track = next(iter(self._tracks.items()))
            if track.last_seen > deadline:
                break
            self._remove(key, changes)
        changes.frames = self._frame_changes({body.frame_id for body in changes.lost})
        return changes

    def next_expiry(self, staleness_s: float | None = None) -> float | None:
        """When ``expire`` has something to do (caller's clock): the oldest body goes
        stale (after ``staleness_s``, by default ``stale_after_s``) or the oldest
        tombstone is forgotten; None when neither exists."""
        when = [next(iter(self._tombstones.values()))[1]] if self._tombstones else []
        if self._tracks:
            stale = self.stale_after_s if staleness_s is None else staleness_s
            when.append(next(iter(self._tracks.values())).last_seen + stale)
        return min(when, default=None)

    def tracked_per_frame(self) -> dict[str, int]:
        """How many bodies each known frame tracks (for the status report)."""
        return {frame_id: len(frame.tracked) for frame_id, frame in self._frames.items()}

    def poses(self, frame_id: str) -> list[tuple[str, Pose]]:
        """The latest pose of every body tracked in a frame (for the scene)."""
        frame = self._frames.get(frame_id)
        bodies = () if frame is None else sorted(frame.tracked)
        return [(b, self._tracks[BodyRef(frame_id=frame_id, body_id=b)].pose) for b in bodies]

    def states(self) -> list[BodyState]:
        """The latest decision of every tracked body."""
        return [track.state for track in self._tracks.values()]

    def frames(self) -> list[FrameFacing]:
        """The aggregate of every known frame, as it stands now."""
        return [
            frame_facing(frame_id, frame.stamp, frame.facing, frame.tracked)
            for frame_id, frame in self._frames.items()
        ]

    def evaluate(self, threshold_deg: float) -> tuple[list[BodyState], list[FrameFacing]]:
        """Re-decide the latest poses under another cone, without hysteresis: for
        queries, a what-if that leaves the tracker's state untouched."""
        samples = [PoseSample(body, track.pose) for body, track in self._tracks.items()]
        same = [threshold_deg] * len(samples)
        profiles = [track.profile for track in self._tracks.values()]
        states = decide(samples, same, profiles, same)
        facing: dict[str, list[str]] = {frame_id: [] for frame_id in self._frames}
        for state in (s for s in states if s.facing):
            facing[state.frame_id].append(state.body_id)
        frames = self._frames.items()
        return states, [frame_facing(f, fr.stamp, facing[f], fr.tracked) for f, fr in frames]

    def _was_facing(self, key: BodyRef) -> bool:
        return (track := self._tracks.get(key)) is not None and track.state.facing

    def _store(
        self,
        sample: PoseSample,
        state: BodyState,
        profile: Profile,
        now: float,
        track: Track | None,
        recent: Window,
    ) -> EngagementUpdate | None:
        """Keep the new state (``track``: the body's, None when new) and its facing window;
        the engagement update to publish, if one is due."""
        key = sample.body
        if track is None:
            track = self._tracks[key] = Track(sample.pose, now, state, profile, recent=recent)
        else:  # in place: the body's engagement carries over
            track.pose, track.last_seen, track.state = sample.pose, now, state
            track.profile, track.recent = profile, recent
        self._tracks.move_to_end(key)
        update = self._engage(track, state, now)
        frame = self._frames.get(sample.frame_id)
        if frame is None:  # (not setdefault: a Frame built for every pose cost 0.4 us)
            frame = self._frames[sample.frame_id] = Frame()
        frame.update(sample.body_id, state.facing)
        if frame.stamp is None or sample.pose.stamp > frame.stamp:
            frame.stamp = sample.pose.stamp
        return update

    def _engage(self, track: Track, state: BodyState, now: float) -> EngagementUpdate | None:
        """Step the body's engagement on the pose's own clock (its stamp): behaviour timing
        is the tracker's. Unchanged levels are republished at most every period of the
        caller's clock (``now``): that limit is about output load, whatever the stamps do."""
        p = track.profile.engagement
        t = state.stamp.seconds
        before = track.engagement.level
        track.engagement = observe(
            track.engagement,
            t,
            p,
            state.angle_deg,
            state.distance_m,
            state.robot_in_body,
            state.position,
        )
        changed = track.engagement.level is not before
        key = state.body
        dwell = track.engagement.level is Level.DISENGAGING and p.model is Model.CONE
        if dwell:  # the cone's dwell running: due even if silent
            left = track.engagement.since + p.disengage_dwell_s - t
            self._due[key] = now + max(0.0, left)
        elif key in self._due:
            del self._due[key]
        if not changed and now - track.engagement_published < self.engagement_period_s:
            return None
        track.engagement_published = now
        return track.engagement_update(before if changed else None)

    def engagements(self) -> list[EngagementUpdate]:
        """The current engagement of every tracked body (for queries)."""
        return [track.engagement_update(None) for track in self._tracks.values()]

    def _remove(self, key: BodyRef, changes: Changes) -> None:
        track = self._tracks.pop(key)
        self._due.pop(key, None)
        if key in self._older:
            del self._older[key]
        if track.engagement.level is not Level.UNKNOWN:  # lost: a last event, to UNKNOWN
            update = track.engagement_update(track.engagement.level)
            changes.engagement.append(replace(update, level=Level.UNKNOWN, since=update.stamp))
        self._frames[key.frame_id].discard(key.body_id)
        changes.lost.append(key)

    def _frame_changes(self, frame_ids: Iterable[str]) -> list[FrameFacing]:
        """Aggregates of the given frames whose lists changed since last published."""
        changed = []
        for frame_id in sorted(frame_ids):
            frame = self._frames[frame_id]
            if frame.dirty:
                frame.dirty = False
                changed.append(frame_facing(frame_id, frame.stamp, frame.facing, frame.tracked))
            if not frame.tracked and frame_id not in self._declared:
                del self._frames[frame_id]
        return changed
