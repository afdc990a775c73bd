"""A client as easy as libhri's HRIListener: ask who faces the robot, react to changes.

    from facing_service import FacingClient

    with FacingClient(frame="base_link", connect=["tcp/192.168.1.10:7447"]) as hri:
        hri.on_facing(lambda state: print("hello", state.body_id))
        print(hri.bodies_facing())

The application never sees a key expression. A local cache, seeded by a query when the
client starts and kept live by a subscription, answers ``bodies`` / ``bodies_facing``
without a network round trip; ``groups`` / ``gazing`` say who stands in a group with whom
(the robot too) and who faces whom. Callbacks fire on transitions only (``on_facing``,
``on_not_facing``, ``on_lost``, ``on_engaged``, ``on_disengaged``, ``on_group_formed`` and
the other group events) or on every result (``on_change``); they run, in order, on the
client's own dispatcher thread, never on zenoh's, so a slow behaviour cannot stall the
session. ``query`` asks the service directly, e.g. with another facing cone; ``status``
says which services answer, and how they are.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable, Iterable
from typing import TypeVar

import zenoh
from typing_extensions import Unpack

from ..config.session import mode_and_endpoints
from ..contract import keys
from ..contract.errors import ClientNotOpen, FacingError, NoService, UnknownFrame
from ..contract.keys import BodyRef
from ..contract.levels import Level
from ..contract.schemas import (
    EngagementEvent,
    FacingState,
    GazePair,
    Greeting,
    GroupState,
    ServiceStatus,
)
from .bodies import BodyCache
from .health import ask, no_service_seen, wait_for_service
from .inbox import Handle, Inbox, Serial, close_at_exit, opened_no_more
from .options import ClientOptionFields, client_options
from .replies import engagement_states, facing_states, waited
from .scene import ClientEvent, Event, SceneListener

log = logging.getLogger("facing_service.client")

StateCallback = Callable[[FacingState], object]
LevelCallback = Callable[[EngagementEvent], object]
LostCallback = Callable[[BodyRef], object]
#: ``callback(frame, group)``; a change also gets the group as it was before.
GroupCallback = Callable[[str, GroupState], object]
GroupChangeCallback = Callable[[str, GroupState, GroupState], object]

#: Calls waiting for the dispatcher: past this, a behaviour slower than the results
#: loses calls (counted, said), not memory.
CALLS_DEPTH = 10_000

C = TypeVar("C", bound=Callable[..., object])


class FacingClient:
    """Live view of the facing service's results. Use as a context manager.

    ``namespace`` is the service's; ``frame`` the base frame the application works in,
    given once (``*``: every frame, and then each read names one). The options say how
    the session reaches the service (``ClientOptions``: ``mode``, ``connect``, ``listen``,
    ``config``, ``cfg``, ``no_multicast_scouting``, ``reconnect_s``, ``timeout_s``, the
    ``tls_*`` files); a ready ``session_config`` replaces the session's. An option the
    client does not take, or a bad value, is a ``SettingsError`` (a ``FacingError``)
    naming it.
    """

    def __init__(
        self,
        namespace: str = "hri",
        frame: str = keys.ALL_FRAMES,
        *,
        session_config: zenoh.Config | None = None,
        **options: Unpack[ClientOptionFields],
    ) -> None:
        self.options = client_options({"namespace": namespace, "frame": frame, **options})
        self.namespace = self.options.namespace
        self.frame = self.options.frame
        self.timeout_s = self.options.timeout_s
        self._config = session_config or self.options.zenoh_config()
        self._lock = threading.Lock()
        self._bodies = BodyCache()  # under the lock
        self._on: dict[ClientEvent, list[Callable[..., object]]] = {}
        self._scene = SceneListener(self.namespace, self.frame, self._is_live, self._emit)
        self._session: zenoh.Session | None = None
        self._inbox: Inbox | None = None  # what zenoh says, in order, on one thread
        self._calls: Serial | None = None  # the callbacks, on another (the dispatcher)
        #: Why no service was seen when the client opened (one line), None when one was.
        self.absence: str | None = None
        # Under the lock: whether open() has begun its own seeding (a service appearing
        # before that is in its answer; one appearing after asks for a re-seed), and that
        # no service knows this client's frame, said once.
        self._seeding = False
        self._said_unknown = False

    # -- lifecycle -------------------------------------------------------------------

    def open(
        self, session: zenoh.Session | None = None, *, log_absence: bool = True
    ) -> FacingClient:
        """Open the session (or take ``session``, one the caller opened: the command line
        opens it patiently while a router is awaited; the client closes it), subscribe,
        wait up to ``timeout_s`` for a service and read its state. No service seen is no
        error (it may start later): ``absence`` then says why, in one line, logged unless
        the caller says it itself (``log_absence=False``)."""
        session = self._session = session if session is not None else zenoh.open(self._config)
        close_at_exit(self)  # at the latest: nothing of it outlives the program
        try:
            self._start(session, log_absence)
            close_at_exit(self)  # again, now newer than its inbox: closed before it
        except BaseException:
            # Ctrl-C while waiting for a service: the callback subscribers' threads would
            # keep the user's program from exiting after its KeyboardInterrupt.
            self.close()
            raise
        return self

    def _start(self, session: zenoh.Session, log_absence: bool) -> None:
        self._calls = Serial("facing-client", CALLS_DEPTH, "callbacks fall behind the results")
        self._inbox = Inbox("facing-client-inbox")
        # Liveliness first (with the tokens already there), so results are judged by
        # who is alive; then subscribe, then seed: a result arriving meanwhile is newer
        # than the query's answer and is kept (states only move forward in stamp order).
        tokens = keys.service_token(self.namespace, "*")
        subscribe = self._inbox.subscribe
        subscribe(session, tokens, self._on_token, tokens=True)
        facing = keys.facing_key(self.namespace, body_id=keys.ALL_FRAMES, frame_id=self.frame)
        subscribe(session, facing, self._on_sample)
        subscribe(session, keys.event_key(self.namespace, self.frame), self._on_event)
        self._scene.open(session, self._inbox)
        found = wait_for_service(session, self.namespace, self.timeout_s, self._seen_alive)
        with self._lock:
            # A token heard after the wait's last look, before this, asked no re-seed
            # the seed below is its, as for one the wait found.
            self._seeding = True
            found = found or bool(self._bodies.live)
        if found:
            self.absence = None
            self._reseed()
        else:
            where = mode_and_endpoints(self._config, "connect")[1]
            self.absence = no_service_seen(session, self.namespace, where)
            if log_absence:
                said = "%s within %.1f s; the cache fills as results arrive"
                log.warning(said, self.absence, self.timeout_s)

    def close(self) -> None:
        """Undeclare everything, stop the dispatcher, close the session. Safe to call
        twice, and from one of the client's own callbacks (its thread is not waited for:
        it ends when the callback returns)."""
        if self._inbox is not None:
            self._inbox.close()
            self._inbox = None
        if self._calls is not None:
            self._calls.stop()
            self._calls = None
        if self._session is not None:
            self._session.close()
            self._session = None
        opened_no_more(self)

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

    def _frame(self, frame: str | None) -> str:
        """The frame a read is about: the client's, or the one named when the client
        watches every frame (naming another frame than the client's is a mistake: its
        cache holds nothing there)."""
        self._open_session()  # a read before open() is a mistake, not an empty answer
        if frame is None or frame == self.frame:
            if self.frame == keys.ALL_FRAMES:
                raise FacingError("this client watches every frame (*): name the frame")
            return self.frame
        if self.frame != keys.ALL_FRAMES:
            raise FacingError(f"this client watches frame {self.frame!r}, not {frame!r}")
        return keys.validate_name(frame, "frame")

    # -- the cache -------------------------------------------------------------------

    def bodies(self, frame: str | None = None) -> dict[str, FacingState]:
        """Every body tracked in the frame, by id, with its latest result."""
        frame = self._frame(frame)
        with self._lock:
            return {b: s for (f, b), s in self._bodies.states.items() if f == frame}

    def bodies_facing(self, frame: str | None = None) -> list[str]:
        """Ids of the bodies facing the robot in the frame, sorted."""
        return sorted(b for b, s in self.bodies(frame).items() if s.facing)

    def engagement(self, frame: str | None = None) -> dict[str, Level]:
        """Every body's current engagement level in the frame, by id (bodies whose level
        the service has not said yet are absent)."""
        frame = self._frame(frame)
        with self._lock:
            levels = self._bodies.levels.items()
            return {b: e.level for (f, b), e in levels if f == frame}

    def groups(self, frame: str | None = None) -> list[GroupState]:
        """The groups in the frame as the service last said them (``robot``: the robot
        is one of the members; ``join``: where the robot should stand to join a group it
        is not in, None when it has no room)."""
        return self._scene.groups(self._frame(frame))

    def greetings(self, frame: str | None = None) -> list[Greeting]:
        """The people ENGAGING or ENGAGED in the frame and in no group, each with where
        the robot should stand to greet them."""
        return self._scene.greetings(self._frame(frame))

    def gazing(self, frame: str | None = None) -> list[GazePair]:
        """Who faces whom in the frame (``""`` is the robot)."""
        return self._scene.gazing(self._frame(frame))

    @property
    def live_instances(self) -> set[str]:
        """The service instances whose liveliness token is seen now."""
        with self._lock:
            return set(self._bodies.live)

    @property
    def dropped_unheard(self) -> int:
        """Samples heard while the client's inbox was full, never filed (a starved client)."""
        return 0 if self._inbox is None else self._inbox.dropped

    @property
    def dropped_callbacks(self) -> int:
        """Calls not made: the callbacks were ``CALLS_DEPTH`` behind (the cache was not)."""
        return 0 if self._calls is None else self._calls.dropped

    def hear(self, key: str, handle: Handle) -> None:
        """``handle`` each sample on ``key`` on the client's thread, in order with the rest."""
        session = self._open_session()
        assert self._inbox is not None  # open
        self._inbox.subscribe(session, key, handle)

    @property
    def dropped_from_dead(self) -> int:
        """Results, levels and scenes said by an instance with no live token, refused."""
        with self._lock:
            return self._bodies.dropped_from_dead + self._scene.dropped_from_dead

    # -- callbacks -------------------------------------------------------------------

    def on_facing(self, callback: StateCallback) -> StateCallback:
        """``callback(state)`` when a body starts facing the robot (or first appears
        facing it). Bodies already facing when it is registered are reported at once."""
        with self._lock:
            current = [s for s in self._bodies.states.values() if s.facing]
            return self._register(ClientEvent.FACING, callback, current)

    def on_not_facing(self, callback: StateCallback) -> StateCallback:
        """``callback(state)`` when a body that faced the robot turns away."""
        return self._register(ClientEvent.NOT_FACING, callback)

    def on_lost(self, callback: LostCallback) -> LostCallback:
        """``callback(body)`` (a ``BodyRef``: ``body.frame_id``, ``body.body_id``) when a
        body is lost (deleted, stale, or its last vouching service gone)."""
        return self._register(ClientEvent.LOST, callback)

    def on_change(self, callback: StateCallback) -> StateCallback:
        """``callback(state)`` for every result."""
        return self._register(ClientEvent.CHANGE, callback)

    def on_engaged(self, callback: LevelCallback) -> LevelCallback:
        """``callback(event)`` when a body becomes ENGAGED (docs/engagement.md). Bodies
        already ENGAGED when it is registered are reported at once, as ``on_facing`` does
        (``previous`` is then the level the client last saw: UNKNOWN for a body that was
        ENGAGED before the client opened)."""
        with self._lock:
            levels = self._bodies.levels.values()
            current = [e for e in levels if e.level is Level.ENGAGED]
            return self._register(ClientEvent.ENGAGED, callback, current)

    def on_disengaged(self, callback: LevelCallback) -> LevelCallback:
        """``callback(event)`` when an engaged body becomes DISENGAGED or is lost."""
        return self._register(ClientEvent.DISENGAGED, callback)

    def on_group_formed(self, callback: GroupCallback) -> GroupCallback:
        """``callback(frame, group)`` when a group forms."""
        return self._register(ClientEvent.GROUP_FORMED, callback)

    def on_group_changed(self, callback: GroupChangeCallback) -> GroupChangeCallback:
        """``callback(frame, group, previous)`` when a group's members change (the robot
        joining or leaving too)."""
        return self._register(ClientEvent.GROUP_CHANGED, callback)

    def on_group_dissolved(self, callback: GroupCallback) -> GroupCallback:
        """``callback(frame, group)`` when a group dissolves (the group as it was)."""
        return self._register(ClientEvent.GROUP_DISSOLVED, callback)

    def on_robot_joined(self, callback: GroupCallback) -> GroupCallback:
        """``callback(frame, group)`` when the robot becomes a member of a group."""
        return self._register(ClientEvent.ROBOT_JOINED, callback)

    def on_robot_left(self, callback: GroupCallback) -> GroupCallback:
        """``callback(frame, group)`` when the robot leaves a group, or the group it was
        in dissolves (the group as it was)."""
        return self._register(ClientEvent.ROBOT_LEFT, callback)

    def _register(self, name: ClientEvent, callback: C, current: Iterable[object] = ()) -> C:
        """Keep ``callback`` for the ``name`` events; report ``current`` to it at once.
        Only on an open client: one never opened would never call it, and
        nothing is missed by registering after open(), as what holds is reported."""
        self._open_session()
        self._on.setdefault(name, []).append(callback)
        for fact in current:
            self._call(callback, fact)
        return callback

    # -- asking the service ----------------------------------------------------------

    def query(
        self, frame: str | None = None, threshold_deg: float | None = None
    ) -> list[FacingState]:
        """The service's current results for the client's frame (or another one, or
        ``*``: the service is asked, not the cache), optionally re-decided under another
        cone (``threshold_deg``, without hysteresis): ``[]`` when nobody is there.
        Raises ``UnknownFrame`` for a frame no service knows (a typo), ``QueryRefused``
        when the service refuses the parameter (both ``ValueError``s), and ``NoService``
        when no service answers at all."""
        asked = self.frame if frame is None else keys.validate_frame_filter(frame)
        return sorted(self._ask(asked, threshold_deg), key=lambda s: s.body_id)

    def status(self) -> list[ServiceStatus]:
        """The status of every live service in the namespace that answers within
        ``timeout_s`` (what ``facing-service health`` prints), by instance; ``NoService``
        when none answers."""
        started = time.monotonic()
        answers = ask(self._open_session(), self.namespace, "*", self.timeout_s)
        if not answers:
            raise NoService(
                f"no facing service in namespace {self.namespace!r} answered its status "
                + waited(started, self.timeout_s)
            )
        return sorted(answers, key=lambda status: status.instance)

    def _ask(self, frame: str, threshold_deg: float | None) -> list[FacingState]:
        selector = keys.facing_key(self.namespace, body_id=keys.ALL_FRAMES, frame_id=frame)
        if threshold_deg is not None:
            selector += f"?threshold_deg={threshold_deg}"
        replies = self._open_session().get(selector, timeout=self.timeout_s)
        return facing_states(replies, selector, bool(self.live_instances), self.timeout_s)

    # -- zenoh side: keep the cache, queue the callbacks -------------------------------

    def _on_token(self, sample: zenoh.Sample) -> None:
        """A service instance appeared or vanished (killed, partitioned, stopped)."""
        instance = keys.instance_of(str(sample.key_expr))
        if sample.kind == zenoh.SampleKind.PUT:
            with self._lock:
                new = instance not in self._bodies.live and self._seeding
                self._bodies.live.add(instance)
            if new:  # re-seed from the dispatcher: never query from the intake
                self._call(self._reseed)
            return
        with self._lock:
            self._emit(self._bodies.instance_gone(instance))
        self._scene.forget(instance)  # outside the lock: the scene's is its own

    def _seen_alive(self, instance: str) -> None:
        with self._lock:
            self._bodies.live.add(instance)

    def _is_live(self, instance: str) -> bool:
        return instance in self._bodies.live  # a set read: atomic under the GIL

    def _emit(self, events: list[Event]) -> None:
        """Queue each event's callbacks, in order (under the lock, or from the scene's)."""
        for name, args in events:
            for callback in self._on.get(name, ()):
                self._call(callback, *args)

    def _reseed(self) -> None:
        """The cache from queries: at start, and when a service (re)appears. Each answer
        is applied as it arrives, never undoing what was heard live since its query
        began (a DELETE meanwhile wins); nobody in this client's frame is no error."""
        try:
            since = time.monotonic()
            states = self._seed_states()
            with self._lock:
                for state in states:
                    self._emit(self._bodies.apply(state, since))
            self._scene.seed(self.session, self.timeout_s, time.monotonic())
            since = time.monotonic()
            selector = keys.engagement_key(self.namespace, body_id="*", frame_id=self.frame)
            levels = engagement_states(self.session.get(selector, timeout=self.timeout_s))
        except Exception as error:  # one line: the cache fills as results arrive
            if self._session is not None:  # (closed meanwhile: nothing to say)
                log.warning("facing client: could not query the service: %s", error,
                            exc_info=not isinstance(error, FacingError))  # fmt: skip
            return
        with self._lock:
            for level in levels:
                seeded = EngagementEvent(previous=Level.UNKNOWN, **level.model_dump())
                self._emit(self._bodies.take_level(seeded, since))

    def _seed_states(self) -> list[FacingState]:
        """The service's results for this client's frame (none for a frame unknown)."""
        try:
            return self._ask(self.frame, None)
        except UnknownFrame as error:  # others are tracked: a misspelt frame, said once
            with self._lock:
                say, self._said_unknown = not self._said_unknown, True
            if say:
                log.warning("facing client: no service knows frame %r yet (%s); a misspelt "
                            "frame stays empty", self.frame, error.detail)  # fmt: skip
            return []

    # The inbox's handlers: one that raises (a bad sample) is logged with its key by the
    # inbox, and the next sample handled.
    def _on_sample(self, sample: zenoh.Sample) -> None:
        with self._lock:
            if sample.kind == zenoh.SampleKind.PUT:
                state = FacingState.model_validate_json(sample.payload.to_bytes())
                self._emit(self._bodies.apply(state))
            else:
                body = keys.body_of(str(sample.key_expr))
                self._emit(self._bodies.delete(body, time.monotonic()))

    def _on_event(self, sample: zenoh.Sample) -> None:
        event = EngagementEvent.model_validate_json(sample.payload.to_bytes())
        with self._lock:
            self._emit(self._bodies.take_level(event))

    def _call(self, callback: Callable[..., object], *args: object) -> None:
        if (calls := self._calls) is not None:  # closed: nobody to call any more
            calls.offer(callback, *args)
