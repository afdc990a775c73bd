"""A client as easy as libhri's HRIListener: ask who faces the robot, react to changes.

    from facing_service import FacingClient

    with FacingClient(connect=["tcp/192.168.1.10:7447"]) as hri:
        hri.on_facing(lambda state: print("hello", state.body_id))
        print(hri.bodies_facing("base_link"))

The application never sees a key expression. A local cache, seeded by a query when the
client starts and kept live by a subscription, answers ``bodies`` / ``bodies_facing``
without a network round trip; ``groups`` / ``gazing`` say who stands in a group with whom
(the robot too) and who faces whom. Callbacks fire on transitions only (``on_facing``,
``on_not_facing``, ``on_lost``, ``on_group``: formed, changed, dissolved, the robot joined
or left) or on every result (``on_change``); they run, in order,
on the client's own dispatcher thread, never on zenoh's, so a slow behaviour cannot stall
the session. ``query`` asks the service directly, e.g. with another facing cone.
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from collections.abc import Callable, Iterable
from typing import Any

import zenoh

from ..config.session import zenoh_config
from ..config.settings import Settings
from ..contract import keys
from ..contract.errors import ClientNotOpen, FacingError, UnknownFrame
from ..contract.levels import Level
from ..contract.schemas import EngagementEvent, FacingState, GazePair, Greeting, GroupState
from ..contract.stamps import Stamp, Time
from .replies import engagement_states, facing_states
from .scene import SCENE_EVENTS, Event, SceneListener

log = logging.getLogger("facing_service.client")

StateCallback = Callable[[FacingState], Any]
EventCallback = Callable[[EngagementEvent], Any]
LostCallback = Callable[[keys.BodyRef], Any]

_STOP = object()

#: The levels at which a body counts as engaged: ``on_disengaged`` follows only these.
_ENGAGED_LEVELS = (Level.ENGAGED, Level.DISENGAGING)


class FacingClient:
    """Live view of the facing service's results. Use as a context manager.

    ``namespace`` is the service's; ``frame`` restricts the view to one base frame (``*``:
    all). The session is configured like the service's (``mode``, ``connect``,
    ``listen``, ``config``, ``cfg``, ``no_multicast_scouting``), or by a ready
    ``session_config``.
    """

    def __init__(
        self,
        namespace: str = "hri",
        frame: str = keys.ALL_FRAMES,
        *,
        session_config: zenoh.Config | None = None,
        timeout_s: float = 2.0,
        **session_flags: Any,
    ) -> None:
        self.namespace = keys.validate_namespace(namespace)
        self.frame = keys.validate_frame_filter(frame)
        self.timeout_s = timeout_s
        self._config = session_config or zenoh_config(Settings(**session_flags))
        self._lock = threading.Lock()
        self._states: dict[keys.BodyRef, FacingState] = {}  # the latest result of each body
        self._on: dict[str, list[Callable[..., Any]]] = {
            "facing": [],
            "not_facing": [],
            "lost": [],
            "change": [],
            "engaged": [],
            "disengaged": [],
            **{event: [] for event in SCENE_EVENTS},
        }
        self._scene = SceneListener(self.namespace, self.frame, self._is_live, self._emit)
        self._events: queue.SimpleQueue[object] = queue.SimpleQueue()
        self._session: zenoh.Session | None = None
        self._subscriber: zenoh.Subscriber[None] | None = None
        self._events_subscriber: zenoh.Subscriber[None] | None = None
        self._liveliness_subscriber: zenoh.Subscriber[None] | None = None
        self._dispatcher: threading.Thread | None = None
        # Who vouches for what: the live service instances (their liveliness tokens), and
        # for each cached body the instances whose results it came from. A body no live
        # instance vouches for is lost: a dead service leaves no ghost.
        self._live: set[str] = set()
        self._vouchers: dict[keys.BodyRef, set[str]] = {}
        # Each body's latest engagement change (seeded at start as previous UNKNOWN).
        self._levels: dict[keys.BodyRef, EngagementEvent] = {}
        self.dropped_from_dead = 0  # results of an instance with no live token, refused

    # -- lifecycle -------------------------------------------------------------------

    def open(self) -> FacingClient:
        self._session = zenoh.open(self._config)
        self._dispatcher = threading.Thread(
            target=self._dispatch, name="facing-client", daemon=True
        )
        self._dispatcher.start()
        # Liveliness first (with the tokens already there), so results are judged by
        # who is alive; then subscribe, then seed: a result arriving meanwhile is newer
        # than the query's answer and is kept (states only move forward in stamp order).
        self._liveliness_subscriber = self._session.liveliness().declare_subscriber(
            keys.service_token(self.namespace, "*"), self._on_token, history=True
        )
        self._subscriber = self._session.declare_subscriber(
            keys.facing_key(self.namespace, keys.ALL_FRAMES, self.frame), self._on_sample
        )
        self._events_subscriber = self._session.declare_subscriber(
            keys.event_key(self.namespace, self.frame), self._on_event
        )
        self._scene.open(self._session)
        if self._wait_for_service():
            self._reseed()
        else:
            log.warning(
                "no facing service seen within %.1f s; the cache fills as results arrive",
                self.timeout_s,
            )
        return self

    def _wait_for_service(self) -> bool:
        """Wait (up to ``timeout_s``) until a service's liveliness token is visible. A
        session just opened may not be connected yet, and the service declares its token
        after its queryables: once the token is seen, the seeding query reaches them."""
        assert self._session is not None
        token = keys.service_token(self.namespace, "*")
        deadline = time.monotonic() + self.timeout_s
        while True:
            found = False
            for reply in self._session.liveliness().get(token, timeout=0.2):
                if reply.ok is not None:
                    with self._lock:
                        self._live.add(_instance_of(str(reply.ok.key_expr)))
                    found = True
            if found:
                return True
            if time.monotonic() >= deadline:
                return False
            time.sleep(0.05)

    def close(self) -> None:
        for subscriber in (
            self._subscriber,
            self._events_subscriber,
            self._liveliness_subscriber,
        ):
            if subscriber is not None:
                subscriber.undeclare()
        self._subscriber = self._events_subscriber = self._liveliness_subscriber = None
        self._scene.close()
        if self._dispatcher is not None:
            self._events.put(_STOP)
            self._dispatcher.join(timeout=2.0)
            self._dispatcher = None
        if self._session is not None:
            self._session.close()
            self._session = None

    def __enter__(self) -> FacingClient:
        return self.open()

    def __exit__(self, *_exc: object) -> None:
        self.close()

    @property
    def session(self) -> zenoh.Session:
        """The client's zenoh session, for applications that need more than results."""
        return self._open_session()

    def _open_session(self) -> zenoh.Session:
        if self._session is None:
            raise ClientNotOpen("the FacingClient is not open: call open(), or use `with`")
        return self._session

    # -- the cache -------------------------------------------------------------------

    def bodies(self, frame: str) -> dict[str, FacingState]:
        """Every body tracked in ``frame``, by id, with its latest result."""
        with self._lock:
            return {b: s for (f, b), s in self._states.items() if f == frame}

    def bodies_facing(self, frame: str) -> list[str]:
        """Ids of the bodies facing the robot in ``frame``, sorted."""
        with self._lock:
            return sorted(b for (f, b), s in self._states.items() if f == frame and s.facing)

    def engagement(self, frame: str) -> dict[str, Level]:
        """Every body's current engagement level in ``frame``, by id (bodies whose level
        the service has not said yet are absent)."""
        with self._lock:
            return {b: Level[e.level] for (f, b), e in self._levels.items() if f == frame}

    def groups(self, frame: str) -> list[GroupState]:
        """The groups in ``frame`` as the service last said them (``robot``: the robot
        is one of the members; ``join``: where the robot should stand to join a group it
        is not in, None when it has no room)."""
        return self._scene.groups(frame)

    def greetings(self, frame: str) -> list[Greeting]:
        """The people ENGAGING or ENGAGED in ``frame`` and in no group, each with where
        the robot should stand to greet them."""
        return self._scene.greetings(frame)

    def gazing(self, frame: str) -> list[GazePair]:
        """Who faces whom in ``frame`` (``""`` is the robot)."""
        return self._scene.gazing(frame)

    # -- callbacks -------------------------------------------------------------------

    def on_group(self, event: str, callback: Callable[..., Any]) -> Callable[..., Any]:
        """``callback(frame, group)`` on ``event``: ``group_formed``, ``group_dissolved``,
        ``robot_joined``, ``robot_left`` (the group as it was), or ``group_changed``
        (``callback(frame, group, previous)``)."""
        if event not in SCENE_EVENTS:
            raise ValueError(f"unknown group event {event!r}; known: {', '.join(SCENE_EVENTS)}")
        self._on[event].append(callback)
        return callback

    def on_facing(self, callback: StateCallback) -> StateCallback:
        """``callback(state)`` when a body starts facing the robot (or first appears
        facing it). Bodies already facing when it is registered are reported at once."""
        with self._lock:
            current = [s for s in self._states.values() if s.facing]
            self._on["facing"].append(callback)
        for state in current:
            self._events.put((callback, (state,)))
        return callback

    def on_not_facing(self, callback: StateCallback) -> StateCallback:
        """``callback(state)`` when a body that faced the robot turns away."""
        self._on["not_facing"].append(callback)
        return callback

    def on_lost(self, callback: LostCallback) -> LostCallback:
        """``callback(body)`` (a ``keys.BodyRef``: ``body.body_id``, ``body.frame_id``) when a body
        is lost (deleted, stale, or its last vouching service gone)."""
        self._on["lost"].append(callback)
        return callback

    def on_change(self, callback: StateCallback) -> StateCallback:
        """``callback(state)`` for every result."""
        self._on["change"].append(callback)
        return callback

    def on_engaged(self, callback: EventCallback) -> EventCallback:
        """``callback(event)`` when a body becomes ENGAGED (docs/engagement.md). Bodies
        already ENGAGED when it is registered are reported at once, as ``on_facing`` does
        (``previous`` is then the level the client last saw: UNKNOWN for a body that was
        ENGAGED before the client opened)."""
        with self._lock:
            current = [e for e in self._levels.values() if e.level == Level.ENGAGED.name]
            self._on["engaged"].append(callback)
        for event in current:
            self._events.put((callback, (event,)))
        return callback

    def on_disengaged(self, callback: EventCallback) -> EventCallback:
        """``callback(event)`` when an engaged body becomes DISENGAGED or is lost."""
        self._on["disengaged"].append(callback)
        return callback

    # -- asking the service ----------------------------------------------------------

    def query(self, frame: str, threshold_deg: float | None = None) -> list[FacingState]:
        """The service's current results for ``frame``, optionally re-decided under
        another cone (``threshold_deg``, without hysteresis): ``[]`` when nobody is there.
        Raises ``UnknownFrame`` for a frame no service knows (a typo), ``QueryRefused``
        when the service refuses the parameter (both ``ValueError``s), and ``NoService``
        when no service answers at all."""
        return sorted(self._ask(frame, threshold_deg), key=lambda s: s.body_id)

    def _ask(self, frame: str | None, threshold_deg: float | None) -> list[FacingState]:
        selector = keys.facing_key(self.namespace, keys.ALL_FRAMES, frame or self.frame)
        if threshold_deg is not None:
            selector += f"?threshold_deg={threshold_deg}"
        replies = self._open_session().get(selector, timeout=self.timeout_s)
        return facing_states(replies, selector, bool(self.live_instances), self.timeout_s)

    @property
    def live_instances(self) -> set[str]:
        """The service instances whose liveliness token is seen now."""
        with self._lock:
            return set(self._live)

    # -- zenoh side: keep the cache, queue the callbacks -------------------------------

    def _on_token(self, sample: zenoh.Sample) -> None:
        """A service instance appeared or vanished (killed, partitioned, stopped)."""
        instance = _instance_of(str(sample.key_expr))
        if sample.kind == zenoh.SampleKind.PUT:
            with self._lock:
                new = instance not in self._live
                self._live.add(instance)
            if new:  # re-seed from the dispatcher: never query from a zenoh callback
                self._events.put((self._reseed, ()))
            return
        with self._lock:
            self._live.discard(instance)
            orphans = []
            for key, vouchers in list(self._vouchers.items()):
                vouchers.discard(instance)
                if not vouchers:
                    orphans.append(key)
            lost = [(key, self._forget(key)) for key in orphans]
            lost_callbacks = list(self._on["lost"])
            disengaged_callbacks = list(self._on["disengaged"])
        for body, last in lost:
            if last is not None and Level[last.level] in _ENGAGED_LEVELS:
                gone = last.model_copy(
                    update={"previous": last.level, "level": "UNKNOWN", "level_value": 0}
                )
                self._queue(disengaged_callbacks, (gone,))
            self._queue(lost_callbacks, (body,))
        self._scene.forget(instance)  # outside the lock: the scene's is its own

    def _is_live(self, instance: str) -> bool:
        return instance in self._live  # a set read: atomic under the GIL

    def _emit(self, events: list[Event]) -> None:
        for name, args in events:
            self._queue(list(self._on[name]), args)

    def _forget(self, key: keys.BodyRef) -> EngagementEvent | None:
        """Drop a body from the cache (lock held); its last engagement change."""
        self._states.pop(key, None)
        self._vouchers.pop(key, None)
        return self._levels.pop(key, None)

    def _reseed(self) -> None:
        """The cache from queries: at start, and when a service (re)appears. A service
        with nobody in this client's frame yet is normal, not an error (it answers
        ``unknown_frame`` until someone is tracked there)."""
        try:
            try:
                states = self._ask(None, None)
            except UnknownFrame:
                states = []
            self._scene.seed(self.session, self.timeout_s)
            selector = keys.engagement_key(self.namespace, keys.ALL_FRAMES, self.frame)
            levels = engagement_states(self.session.get(selector, timeout=self.timeout_s))
        except FacingError as error:  # said in one line: the cache fills as results arrive
            log.warning("facing client: could not query the service: %s", error)
            return
        except Exception:
            log.exception("facing client: could not query the service")
            return
        for state in states:
            self._apply(state)
        for level in levels:
            self._take_event(
                EngagementEvent(previous=Level.UNKNOWN.name, **level.model_dump()),
            )

    def _on_sample(self, sample: zenoh.Sample) -> None:
        try:
            if sample.kind == zenoh.SampleKind.PUT:
                self._apply(FacingState.model_validate_json(sample.payload.to_bytes()))
                return
            body = keys.body_of(str(sample.key_expr))
            with self._lock:
                known = body in self._states
                self._forget(body)
                callbacks = list(self._on["lost"]) if known else []
            self._queue(callbacks, (body,))
        except Exception:  # a bad sample must never break the subscription
            log.exception("facing client: could not handle a sample on %s", sample.key_expr)

    def _on_event(self, sample: zenoh.Sample) -> None:
        try:
            event = EngagementEvent.model_validate_json(sample.payload.to_bytes())
        except Exception:
            log.exception("facing client: could not read an engagement event")
            return
        self._take_event(event)

    def _take_event(self, event: EngagementEvent) -> None:
        """A change of level, said or seeded: kept, and the callbacks of the transition
        from the level the client last saw (an older change, raced by the seed, is not)."""
        level = Level[event.level]
        key = keys.BodyRef(frame_id=event.frame_id, body_id=event.body_id)
        with self._lock:
            if event.instance is not None and event.instance not in self._live:
                self.dropped_from_dead += 1
                return
            known = self._levels.get(key)
            if known is not None and _time(known.stamp) > _time(event.stamp):
                return
            previous = known.level if known is not None else event.previous
            was_engaged = Level[previous] in _ENGAGED_LEVELS
            if level is Level.UNKNOWN:
                self._levels.pop(key, None)
            else:
                self._levels[key] = event
        if level is Level.ENGAGED and not was_engaged:
            self._queue(list(self._on["engaged"]), (event,))
        elif level in (Level.DISENGAGED, Level.UNKNOWN) and was_engaged:
            self._queue(list(self._on["disengaged"]), (event,))

    def _apply(self, state: FacingState) -> None:
        key = keys.BodyRef(frame_id=state.frame_id, body_id=state.body_id)
        with self._lock:
            if state.instance is not None and state.instance not in self._live:
                self.dropped_from_dead += 1  # said by an instance no longer (or not yet) alive
                return
            previous = self._states.get(key)
            if previous is not None and _time(previous.stamp) > _time(state.stamp):
                return  # older than what we have (the seeding query raced a result)
            self._states[key] = state
            if state.instance is not None:
                self._vouchers.setdefault(key, set()).add(state.instance)
            was_facing = previous is not None and previous.facing
            callbacks = list(self._on["change"])
            if state.facing and not was_facing:
                callbacks += self._on["facing"]
            elif was_facing and not state.facing:
                callbacks += self._on["not_facing"]
        self._queue(callbacks, (state,))

    def _queue(self, callbacks: Iterable[Callable[..., Any]], args: tuple[Any, ...]) -> None:
        for callback in callbacks:
            self._events.put((callback, args))

    def _dispatch(self) -> None:
        while (event := self._events.get()) is not _STOP:
            callback, args = event  # type: ignore[misc]
            try:
                callback(*args)
            except Exception:
                log.exception("facing client: a callback raised")


def _instance_of(token_key: str) -> str:
    """``NS/services/facing/<instance>`` -> ``<instance>``."""
    return token_key.rsplit("/", 1)[-1]


def _time(stamp: Stamp) -> Time:
    return Time.from_model(stamp)
