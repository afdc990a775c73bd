"""The client's view of each frame's social scene: its groups and who faces whom, as the
service last said them, and what changed as callback events. ``SceneCache`` is pure;
``SceneListener`` feeds it from zenoh (subscriptions, and queries when a service
appears) for ``FacingClient``, which queues the events on its dispatcher.

Events: ``group_formed(frame, group)``, ``group_changed(frame, group, previous)``,
``group_dissolved(frame, group)``, ``robot_joined(frame, group)`` and
``robot_left(frame, group)`` (the group the robot was in, as it was).
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from enum import Enum
from typing import Any

import zenoh

from ..contract import keys
from ..contract.schemas import FrameGazing, FrameGroups, GazePair, Greeting, GroupState
from ..contract.stamps import Time
from .inbox import Inbox

log = logging.getLogger("facing_service.client")


class ClientEvent(str, Enum):
    """What ``FacingClient``'s callbacks are registered for (its ``on_<event>`` methods)."""

    CHANGE = "change"
    FACING = "facing"
    NOT_FACING = "not_facing"
    LOST = "lost"
    ENGAGED = "engaged"
    DISENGAGED = "disengaged"
    GROUP_FORMED = "group_formed"
    GROUP_CHANGED = "group_changed"
    GROUP_DISSOLVED = "group_dissolved"
    ROBOT_JOINED = "robot_joined"
    ROBOT_LEFT = "robot_left"


#: An event and its callback's arguments.
Event = tuple[ClientEvent, tuple[Any, ...]]


class SceneCache:
    """The latest groups and pairs per frame, newest stamp wins (a seeding query may race
    a publication), and the frames each service instance vouches for. A frame whose
    groups all dissolved is forgotten, and when that was heard is kept: a seed begun
    before it cannot bring the groups back."""

    def __init__(self) -> None:
        self._groups: dict[str, FrameGroups] = {}
        self._gazing: dict[str, FrameGazing] = {}
        self._emptied: dict[str, float] = {}  # frame -> when its groups were said empty

    def groups(self, frame: str) -> list[GroupState]:
        said = self._groups.get(frame)
        return [] if said is None else list(said.groups)

    def gazing(self, frame: str) -> list[GazePair]:
        said = self._gazing.get(frame)
        return [] if said is None else list(said.pairs)

    def greetings(self, frame: str) -> list[Greeting]:
        said = self._groups.get(frame)
        return [] if said is None else list(said.greetings)

    def apply_groups(
        self, said: FrameGroups, now: float, seeded_since: float | None = None
    ) -> list[Event]:
        """A frame's groups heard at ``now`` (the caller's clock), live or seeded by a
        query begun at ``seeded_since``."""
        before = self._groups.get(said.frame)
        if before is not None and _stamp(before) > _stamp(said):
            return []
        if seeded_since is not None and self._emptied.get(said.frame, -1.0) >= seeded_since:
            return []  # emptied since the seed began: its view is older
        if said.groups or said.greetings:
            self._groups[said.frame] = said
            self._emptied.pop(said.frame, None)
        else:  # nobody grouped: forgotten (the service forgets an empty frame, and its
            self._groups.pop(said.frame, None)  # stamps may start over when it returns)
            if seeded_since is None:
                self._emptied[said.frame] = now
        return changes(said.frame, [] if before is None else before.groups, said.groups)

    def apply_gazing(self, said: FrameGazing) -> None:
        before = self._gazing.get(said.frame)
        if before is None or _stamp(before) <= _stamp(said):
            self._gazing[said.frame] = said

    def forget(self, instance: str) -> list[Event]:
        """A service instance vanished: what it said goes, its groups dissolve."""
        events: list[Event] = []
        for frame, said in list(self._groups.items()):
            if said.instance == instance:
                del self._groups[frame]
                events += changes(frame, said.groups, [])
        for frame, pairs in list(self._gazing.items()):
            if pairs.instance == instance:
                del self._gazing[frame]
        return events


class SceneListener:
    """Subscriptions to a frame filter's groups and pairs, a seeding query, the cache.
    ``is_live(instance)`` says whether a service instance is alive (what a dead one said
    is refused, counted in ``dropped_from_dead``); ``emit(events)`` queues callbacks."""

    def __init__(
        self,
        namespace: str,
        frame: str,
        is_live: Callable[[str], bool],
        emit: Callable[[list[Event]], None],
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self._keys: dict[str, type[FrameGroups] | type[FrameGazing]] = {
            keys.groups_key(namespace, frame): FrameGroups,
            keys.gazing_key(namespace, frame): FrameGazing,
        }
        self._gazing_prefix = keys.gazing_key(namespace, "")
        self._is_live, self._emit, self._clock = is_live, emit, clock
        self._lock = threading.Lock()
        self._cache = SceneCache()
        self.dropped_from_dead = 0

    def open(self, session: zenoh.Session, inbox: Inbox) -> None:
        """Hear the groups and pairs on the client's ``inbox`` (it closes them)."""
        for key in self._keys:  # one by one: a Ctrl-C meanwhile closes those declared
            inbox.subscribe(session, key, self._on_sample)

    def seed(self, session: zenoh.Session, timeout_s: float, since: float) -> None:
        """What the services say now (at start, and when one appears), asked at ``since``
        (the client's clock)."""
        for key, model in self._keys.items():
            for reply in session.get(key, timeout=timeout_s):
                if reply.ok is not None:
                    self._take(model.model_validate_json(reply.ok.payload.to_bytes()), since)

    def groups(self, frame: str) -> list[GroupState]:
        with self._lock:
            return self._cache.groups(frame)

    def gazing(self, frame: str) -> list[GazePair]:
        with self._lock:
            return self._cache.gazing(frame)

    def greetings(self, frame: str) -> list[Greeting]:
        with self._lock:
            return self._cache.greetings(frame)

    def forget(self, instance: str) -> None:
        with self._lock:
            self._emit(self._cache.forget(instance))

    def _on_sample(self, sample: zenoh.Sample) -> None:
        try:
            gazing = str(sample.key_expr).startswith(self._gazing_prefix)
            model = FrameGazing if gazing else FrameGroups
            said = model.model_validate_json(sample.payload.to_bytes())
        except Exception:  # a bad sample must never break the subscription
            log.exception("facing client: could not read %s", sample.key_expr)
            return
        self._take(said)

    def _take(self, said: FrameGroups | FrameGazing, seeded_since: float | None = None) -> None:
        """From the inbox's thread and the seeding one: the count under the lock too
        (``+= 1`` outside it, from three threads, could lose counts)."""
        with self._lock:
            if said.instance is not None and not self._is_live(said.instance):
                self.dropped_from_dead += 1
                return
            if isinstance(said, FrameGazing):
                self._cache.apply_gazing(said)
                return
            # queued under the lock: the callbacks come in the order the cache changed
            # (the seeding thread and the inbox both apply groups)
            self._emit(self._cache.apply_groups(said, self._clock(), seeded_since))


def changes(frame: str, before: list[GroupState], after: list[GroupState]) -> list[Event]:
    """The events between two lists of a frame's groups, matched by id."""
    old = {g.id: g for g in before}
    new = {g.id: g for g in after}
    events: list[Event] = []
    for gid, group in new.items():
        previous = old.get(gid)
        if previous is None:
            events.append((ClientEvent.GROUP_FORMED, (frame, group)))
        elif previous.members != group.members or previous.robot != group.robot:
            events.append((ClientEvent.GROUP_CHANGED, (frame, group, previous)))
        if group.robot and (previous is None or not previous.robot):
            events.append((ClientEvent.ROBOT_JOINED, (frame, group)))
        if previous is not None and previous.robot and not group.robot:
            events.append((ClientEvent.ROBOT_LEFT, (frame, previous)))
    for gid, group in old.items():
        if gid not in new:
            events.append((ClientEvent.GROUP_DISSOLVED, (frame, group)))
            if group.robot:
                events.append((ClientEvent.ROBOT_LEFT, (frame, group)))
    return events


def _stamp(said: FrameGroups | FrameGazing) -> Time:
    return Time.from_model(said.stamp)
