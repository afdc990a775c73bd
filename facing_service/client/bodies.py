"""The client's view of each body: its latest result and engagement level, which live
service instances vouch for it, and what each new fact means as callback events. Pure (no
zenoh, no lock, no thread): ``FacingClient`` feeds it under its lock and queues the events
it returns on its dispatcher.

Events: ``facing(state)``, ``not_facing(state)``, ``change(state)``, ``lost(body)``,
``engaged(event)``, ``disengaged(event)``.

One order decides: a live result or level replaces an older one (stamps), and a seed (a
query's answer, applied after it arrives) never undoes what was heard live since the
query began: a DELETE heard meanwhile leaves a tombstone (when it was heard, on the
caller's clock) that refuses the seed's older view of that body.
"""

from __future__ import annotations

from collections import OrderedDict

from ..contract.keys import BodyRef
from ..contract.levels import Level
from ..contract.schemas import EngagementEvent, FacingState
from ..contract.stamps import Time
from .scene import ClientEvent, Event

#: The levels at which a body counts as engaged: ``disengaged`` follows only these.
ENGAGED_LEVELS = (Level.ENGAGED, Level.DISENGAGING)
#: DELETEs remembered against seeds still under way (the newest kept): a seed takes at
#: most a few timeouts, and a room does not lose this many people meanwhile.
TOMBSTONES = 10_000


class BodyCache:
    """Results and levels, newest stamp wins (a seeding query may race a publication);
    what an instance that is not alive says is refused and counted (``dropped_from_dead``):
    a dead service leaves no ghost."""

    def __init__(self) -> None:
        self.live: set[str] = set()  # the service instances whose token is seen now
        self.states: dict[BodyRef, FacingState] = {}
        self.levels: dict[BodyRef, EngagementEvent] = {}
        self._vouchers: dict[BodyRef, set[str]] = {}
        # body -> when its DELETE was heard (the caller's clock), oldest first
        self._deleted: OrderedDict[BodyRef, float] = OrderedDict()
        self.dropped_from_dead = 0
        self.seeds_refused = 0  # seeded facts about bodies deleted since the seed began

    def _refused(self, key: BodyRef, instance: str | None, seeded_since: float | None) -> bool:
        """Whether a fact is refused: said by an instance not alive, or seeded by a query
        that began before the body's DELETE was heard. A live fact ends a tombstone."""
        if instance is not None and instance not in self.live:
            self.dropped_from_dead += 1  # said by an instance no longer (or not yet) alive
            return True
        if seeded_since is None:
            self._deleted.pop(key, None)
        elif self._deleted.get(key, seeded_since - 1.0) >= seeded_since:
            self.seeds_refused += 1
            return True
        return False

    def apply(self, state: FacingState, seeded_since: float | None = None) -> list[Event]:
        """A result, said (live) or seeded (by a query begun at ``seeded_since``)."""
        key = BodyRef(frame_id=state.frame_id, body_id=state.body_id)
        if self._refused(key, state.instance, seeded_since):
            return []
        previous = self.states.get(key)
        if previous is not None and _time(previous) > _time(state):
            return []  # older than what we have (the seeding query raced a result)
        self.states[key] = state
        if state.instance is not None:
            self._vouchers.setdefault(key, set()).add(state.instance)
        was_facing = previous is not None and previous.facing
        events: list[Event] = [(ClientEvent.CHANGE, (state,))]
        if state.facing and not was_facing:
            events.append((ClientEvent.FACING, (state,)))
        elif was_facing and not state.facing:
            events.append((ClientEvent.NOT_FACING, (state,)))
        return events

    def take_level(self, event: EngagementEvent, seeded_since: float | None = None) -> list[Event]:
        """A change of level, said or seeded: kept, and the events of the transition from
        the level last seen (an older change, raced by the seed, is not)."""
        level = event.level
        key = BodyRef(frame_id=event.frame_id, body_id=event.body_id)
        if self._refused(key, event.instance, seeded_since):
            return []
        known = self.levels.get(key)
        if known is not None and _time(known) > _time(event):
            return []
        previous = known.level if known is not None else event.previous
        was_engaged = previous in ENGAGED_LEVELS
        if level is Level.UNKNOWN:
            self.levels.pop(key, None)
        else:
            self.levels[key] = event
        if level is Level.ENGAGED and not was_engaged:
            return [(ClientEvent.ENGAGED, (event,))]
        if level in (Level.DISENGAGED, Level.UNKNOWN) and was_engaged:
            return [(ClientEvent.DISENGAGED, (event,))]
        return []

    def delete(self, body: BodyRef, now: float) -> list[Event]:
        """The service deleted a body's result (gone from its frame, or stale), heard at
        ``now`` (the caller's clock): a seed begun before then cannot bring it back."""
        known = body in self.states
        self._forget(body)
        self._deleted.pop(body, None)
        self._deleted[body] = now
        while len(self._deleted) > TOMBSTONES:
            self._deleted.popitem(last=False)
        return [(ClientEvent.LOST, (body,))] if known else []

    def instance_gone(self, instance: str) -> list[Event]:
        """A service instance vanished: the bodies it alone vouched for are lost (and
        disengaged first, when they were engaged)."""
        self.live.discard(instance)
        orphans = []
        for key, vouchers in list(self._vouchers.items()):
            vouchers.discard(instance)
            if not vouchers:
                orphans.append(key)
        events: list[Event] = []
        for body in orphans:
            last = self._forget(body)
            if last is not None and last.level in ENGAGED_LEVELS:
                gone = last.model_copy(
                    update={"previous": last.level, "level": Level.UNKNOWN, "level_value": 0}
                )
                events.append((ClientEvent.DISENGAGED, (gone,)))
            events.append((ClientEvent.LOST, (body,)))
        return events

    def _forget(self, body: BodyRef) -> EngagementEvent | None:
        """Drop a body; its last engagement change."""
        self.states.pop(body, None)
        self._vouchers.pop(body, None)
        return self.levels.pop(body, None)


def _time(said: FacingState | EngagementEvent) -> Time:
    return Time.from_model(said.stamp)
