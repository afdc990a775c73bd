"""The zenoh shell: subscribe to poses, run the core, publish results, answer queries.
``FacingService`` owns the session, its entities and threads, and the status; each job is
a collaborator's (the worker's loop in ``worker``; the input and output forms, made by
``forms``, in ``inputs``, ``ros_input`` and ``outputs``).

Threads, and why:
- the worker (``worker``): owns the tracker and the robot's state. Pulls input samples
  straight from zenoh's channel, and queries (and a robot's other topics) from the side
  queue the callbacks fill, in arrival order (see ``intake``); handles them in batches,
  hands publications to the outbox, answers queries in order with the samples. Bounded:
  when the channel is full zenoh's receive thread waits, which pushes back to the senders
  (trackers publishing with BLOCK slow down; nothing is dropped here).
- zenoh callbacks (queries, a robot's other topics): only queue the item for the worker.
  A slow callback would stall every subscriber of the session.
- the alarm (``intake``): wakes a waiting worker at its next deadline.
- the link watch (``links``): says when no router or peer is reachable, and when one is
  again (the status's ``outage_s``).
Every one of them is watched: the status says ``failed`` when one has died.
- the publisher (``publisher``): sends what the outbox holds, with BLOCK. A slow consumer
  slows it down; one that stops reading blocks it (up to zenoh's ``wait_before_close``).
  Only this thread waits, while the worker keeps ingesting, deciding and answering.
- the status queryable answers from the ledger in its callback, so a health check gets an
  answer even when the worker is behind a backlog.

What is said is built by pure functions (``publications``); what is counted, and how it is
read consistently, lives in ``ledger``.

Congestion control (docs/contract.md): our JSON keys go out with BLOCK, from the publisher
thread only, so nothing is dropped silently (the robot's keep-last topics with DROP, as
rmw_zenoh's own publishers, see ``ros_bus``). A slow consumer slows everything down (the
worker waits for room in the outbox); per-body results are superseded (counted) only
when the publisher has moved nothing for 0.5 s, and aggregates and DELETEs never are.
(DROP for per-body results lost 2.5 % of a 100 000-pose burst to a consumer that was
merely slower than the burst, and made nothing faster; see benchmarks.)
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable

import zenoh

from ..config.disclosure import public_endpoints, public_settings
from ..config.session import effective_session, mode_and_endpoints, zenoh_config
from ..config.settings import Settings
from ..config.version import VERSION
from ..contract import keys
from ..contract.schemas import InputHealth, ServiceStatus
from ..core.silence import InputSilence
from .compose import answers_for, parts_for, silent_after_in_force
from .decisions import Decisions
from .intake import Intake
from .json_sender import JSON
from .ledger import Ledger
from .links import NO_ROUTER_AFTER_S, LinkWatch
from .neighbours import Neighbours
from .outbox import Outbox
from .outputs import JsonOutput
from .publications import QuerySpace
from .publisher import Publisher
from .queries import QueryItem
from .threads import daemon_thread
from .worker import Worker

log = logging.getLogger("facing_service")

#: Intake bound before zenoh pushes back. Queued zenoh samples hold native memory: under a
#: sustained flood (python -m benchmarks.perf.soak) an 8192-deep intake let the service's RSS
#: climb to a ~350 MB plateau; 1024 keeps it flat (~134 MB with 10 000 bodies tracked) at
#: the same throughput, since batches are at most MAX_BATCH anyway.
INBOX_SIZE = 1024

#: How long closing waits for the service's threads, all of them together (then the
#: session's close releases any still blocked): SIGTERM ends the process within 2 s.
CLOSE_JOIN_S = 1.0


def query_spaces(namespace: str) -> dict[QuerySpace, str]:
    """Each query space's key expression. Every frame, even with a fixed --base-frame: a
    query on another frame (a typo) is answered unknown_frame, naming this service's
    frames, not left unanswered (the client then said [] where docs promise an
    error)."""
    body_space, frame_space = keys.result_queryables(namespace)
    return {
        QuerySpace.FACING: body_space,
        QuerySpace.FRAME: frame_space,
        QuerySpace.ENGAGEMENT: keys.engagement_key(
            namespace, body_id=keys.ALL_FRAMES, frame_id=keys.ALL_FRAMES
        ),
        QuerySpace.GROUPS: keys.groups_key(namespace, keys.ALL_FRAMES),
        QuerySpace.GAZING: keys.gazing_key(namespace, keys.ALL_FRAMES),
    }


class FacingService:
    """One running facing service on one zenoh session.

    Use as a context manager, or ``start()`` then ``close()``. ``clock`` is the monotonic
    clock used for staleness; tests may inject their own.
    """

    def __init__(self, settings: Settings, clock: Callable[[], float] = time.monotonic) -> None:
        self.settings = settings
        self._clock = clock
        self._started_at = clock()
        self._outbox = Outbox()
        self._closing = threading.Event()
        self._ledger = Ledger(clock)
        self._parts = parts_for(settings, self._ledger, clock)  # the composition root's
        self._tracker, self._input, self._outputs = (
            self._parts.tracker,
            self._parts.source,
            self._parts.outputs,
        )
        #: our JSON keys (always among the outputs): the status says whether they are heard
        self._json_output = next(o for o in self._outputs if isinstance(o, JsonOutput))
        self._intake: Intake | None = None
        self._worker: Worker | None = None  # made once the session is open
        self._session: zenoh.Session | None = None
        self._entities: list[zenoh.Subscriber[None] | zenoh.Queryable[None]] = []
        self._token: zenoh.LivelinessToken | None = None
        self._neighbours: Neighbours | None = None
        self._threads: list[threading.Thread] = []
        self._link_watch: LinkWatch | None = None
        self._session_in_force: dict[str, object] = {}  # mode and scouting in force (status)

    # -- lifecycle -------------------------------------------------------------------

    def start(self) -> FacingService:
        s = self.settings
        ns = s.namespace
        conf = zenoh_config(s)
        self._session_in_force = effective_session(s, conf)
        self._session = session = zenoh.open(conf)
        _, endpoints = mode_and_endpoints(conf, "connect")
        self._link_watch = LinkWatch(self.connected, endpoints, time.monotonic, self._closing)
        try:
            self._intake = Intake(
                session, self._input.hot_key(), INBOX_SIZE, self._closing, self._clock
            )
            subscription = self._input.open(session, self._enqueue)
            intake, clock = self._intake, self._clock
            for output in self._outputs:
                output.wake_with(lambda: intake.set_alarm(clock()))
            decisions = Decisions(self._parts, self._ledger, self._outbox)
            self._worker = worker = Worker(
                decisions, self._intake, answers_for(s, self._ledger), clock, self._closing
            )
            worker.first_aggregates()
            publisher = Publisher(session, self._outbox, self._ledger, self._closing, self._outputs)
            self._threads = [
                daemon_thread(worker.run, "facing-worker"),
                daemon_thread(publisher.run, "facing-publish"),
                daemon_thread(self._link_watch.run, "facing-links"),
            ]
            for thread in self._threads:
                thread.start()
            spaces = query_spaces(ns)
            # The status first: declarations reach a router in order, so whoever has an
            # answer on the results' spaces can ask the status too (CI once asked between).
            self._entities = [
                session.declare_queryable(keys.status_key(ns, s.instance), self._on_status),
                *(self._queryable(session, space, key) for space, key in spaces.items()),
            ]
            self._token = session.liveliness().declare_token(keys.service_token(ns, s.instance))
            self._neighbours = Neighbours(session, ns, s.base_frame)
        except BaseException:
            self.close()
            raise
        self._say_started(session, subscription, spaces)
        return self

    def _say_started(
        self, session: zenoh.Session, subscription: str, spaces: dict[QuerySpace, str]
    ) -> None:
        """The start line, and a setting changed to fit another (the status shows it in
        force)."""
        s = self.settings
        log.info(
            "facing-service %s started: instance %s, zenoh id %s, %s; poses from %s; results "
            "on %s and %s (queryable); status on %s; threshold %.1f deg, hysteresis %.1f deg, "
            "stale after %.1f s, at most %d bodies%s",
            VERSION,
            s.instance,
            session.zid(),
            self._links(),
            subscription,
            spaces[QuerySpace.FACING],
            spaces[QuerySpace.FRAME],
            keys.status_key(s.namespace, s.instance),
            s.threshold_deg,
            s.hysteresis_deg,
            s.stale_after_s,
            s.max_bodies,
            self._input.start_line() + "".join(o.start_line() for o in self._outputs),
        )
        if (in_force := silent_after_in_force(s)) != s.silent_after_s:
            log.warning(
                "--silent-after-s %g is more than half of --stale-after-s %g: %g is in "
                "force (a silence must be noticed before anyone goes stale)",
                s.silent_after_s, s.stale_after_s, in_force,
            )  # fmt: skip

    def _in_force(self) -> dict[str, object]:
        """Settings as they are in force where they differ from what was set."""
        return self._session_in_force | {"silent_after_s": silent_after_in_force(self.settings)}

    def _queryable(
        self, session: zenoh.Session, space: QuerySpace, key: str
    ) -> zenoh.Queryable[None]:
        """A queryable whose queries the worker answers in order with the samples."""
        return session.declare_queryable(key, lambda q: self._enqueue(QueryItem(q, space)))

    def _links(self) -> str:
        """Mode and endpoints, as the start line says them (no secret: see disclosure)."""
        conf = zenoh_config(self.settings)
        said = {}
        for kind in ("connect", "listen"):
            mode, endpoints = mode_and_endpoints(conf, kind)
            said[kind] = public_endpoints(endpoints) or "none"
        return f"mode {mode}, connect {said['connect']}, listen {said['listen']}"

    def close(self) -> None:
        """Stop taking input, stop the threads, close the session. Idempotent.

        Bounded so that SIGTERM exits within 2 s even during a flood (the backlog is
        abandoned) or with a publisher blocked on a stuck consumer (closing the session
        releases it).
        """
        self._closing.set()
        if self._neighbours is not None:
            self._neighbours.close()
            self._neighbours = None
        if self._token is not None:
            self._token.undeclare()
            self._token = None
        for entity in self._entities:
            entity.undeclare()
        self._entities = []
        self._input.close()
        if self._intake is not None:  # a waiting worker wakes; a busy one sees the flag
            self._intake.close()
        self._outbox.close()
        deadline = time.monotonic() + CLOSE_JOIN_S  # one budget (0.7 s each was 2.1 s)
        for thread in self._threads:
            thread.join(timeout=max(deadline - time.monotonic(), 0.0))
        self._threads = []
        if self._session is not None:
            self._session.close()
            self._session = None

    def __enter__(self) -> FacingService:
        return self.start()

    def __exit__(self, *_exc: object) -> None:
        self.close()

    @property
    def zid(self) -> str:
        assert self._session is not None, "service not started"
        return str(self._session.zid())

    def connected(self) -> dict[str, list[str]]:
        """The routers and peers the session is connected to now (zenoh ids)."""
        session = self._session
        if session is None:
            return {"routers": [], "peers": []}
        return {
            "routers": sorted(str(z) for z in session.info.routers_zid()),
            "peers": sorted(str(z) for z in session.info.peers_zid()),
        }

    def status(self) -> ServiceStatus:
        """A consistent snapshot of health, counters and state sizes; thread-safe. Health
        is read after the counters: the worker says "degraded" before it counts an error,
        so a status that shows the error says degraded (unless a batch succeeded since)."""
        outage = None if self._link_watch is None else self._link_watch.outage_s()
        snapshot = self._ledger.status(
            self._outbox,
            status="ok",
            instance=self.settings.instance,
            version=VERSION,
            zenoh_id=str(self._session.zid()) if self._session is not None else "",
            uptime_s=round(self._clock() - self._started_at, 3),
            config=public_settings(self.settings.model_dump(mode="json") | self._in_force()),
            connected=self.connected(),
            outage_s=None if outage is None else round(outage, 3),
            inbox_depth=len(self._intake) if self._intake is not None else 0,
            results_heard=self._json_output.results_heard,
            input=None if self._worker is None else self._input_health(self._worker.silence),
            ros2=self._input.status(),
        )
        alive = (
            bool(self._threads)
            and all(t.is_alive() for t in self._threads)
            and (self._intake is None or self._intake.alive)
        )
        failing = self._worker is not None and self._worker.faults.failing
        health = "failed" if not alive else "degraded" if failing else "ok"
        if health == "ok" and outage is not None and outage > NO_ROUTER_AFTER_S:
            health = "no router"
        return snapshot.model_copy(update={"status": health})

    def _input_health(self, silence: InputSilence) -> InputHealth:
        """The input as the worker last judged it (plain fields it alone writes)."""
        heard, holding = silence.last_heard, silence.stalled
        return InputHealth(
            last_heard_s=None if heard is None else round(self._clock() - heard, 3),
            silent=holding,
            held=sum(self._ledger.tracked.values()) if holding else 0,
            silences=silence.silences,
            longest_silence_s=round(silence.longest_s, 3),
        )

    # -- zenoh callbacks: hand off, nothing else ---------------------------------------

    def _enqueue(self, item: object) -> None:
        assert self._intake is not None
        self._intake.put(item)  # waits while full

    def _on_status(self, query: zenoh.Query) -> None:
        key = keys.status_key(self.settings.namespace, self.settings.instance)
        query.reply(key, self.status().model_dump_json(), encoding=JSON)
        query.drop()
