"""The zenoh shell: subscribe to poses, run the core, publish results, answer queries.

Threads, and why:
- zenoh callbacks (its own threads): only stamp the arrival time and put the sample or
  query in the inbox. A slow callback would stall every subscriber of the session. The
  inbox is bounded; when it is full the callback waits, which pushes back through zenoh to
  the senders (trackers publishing with BLOCK slow down; nothing is dropped here).
- the worker: owns the tracker. Drains the inbox in batches (one vectorized core call per
  batch), hands publications to the outbox, answers queries in order with the samples.
- the publisher: sends what the outbox holds, with BLOCK. A slow consumer slows it down;
  one that stops reading blocks it (up to zenoh's ``wait_before_close``). Only this
  thread waits, while the worker keeps ingesting, deciding and answering (see ``outbox``).
- the status queryable answers from a snapshot in its callback, so a health check gets an
  answer even when the worker is behind a backlog.

Congestion control (see the README): every output is BLOCK and sent by the publisher
thread only, so nothing is dropped silently. Per-body results are superseded (counted)
only while 10 000 publications wait in the outbox; aggregates and DELETEs never are.
(DROP for per-body results lost 2.5 % of a 100 000-pose burst to a consumer that was
merely slower than the burst, and made nothing faster; see benchmarks.)
"""

from __future__ import annotations

import logging
import math
import threading
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass

import zenoh

from . import __version__, keys
from .config import Settings, mode_and_endpoints, zenoh_config
from .disclosure import public_endpoint, public_settings
from .engagement import Level
from .inbox import Inbox
from .outbox import Kind, Outbox, Publication
from .people import People
from .ros2_input import Ros2Subscriptions, RosSample, route
from .ros2_output import RosMessage, RosOutput, RosPublishers
from .ros2_wire import RosFormat, Wire
from .schemas import (
    EngagementEvent,
    EngagementState,
    FrameFacing,
    QueryError,
    Rejected,
    Rejection,
    ServiceStatus,
    Stamp,
    decode_pose,
)
from .tracker import Changes, EngagementUpdate, PoseSample, Tracker

log = logging.getLogger("facing_service")

JSON = zenoh.Encoding.APPLICATION_JSON
#: Most inbox items handled per batch: bounds the latency a backlog adds to a query.
MAX_BATCH = 1024
#: Inbox bound before the callbacks push back. Queued zenoh samples hold native memory:
#: under a sustained flood (python -m benchmarks.soak) an 8192-deep inbox let the service's
#: RSS climb to a ~350 MB plateau; 1024 keeps it flat (~134 MB with 10 000 bodies tracked)
#: at the same throughput, since batches are at most MAX_BATCH anyway.
INBOX_SIZE = 1024
#: Rejections are summarized in the log at most this often, never one line per sample.
REJECTION_LOG_PERIOD_S = 5.0
#: Selector parameters the queryable understands; zenoh reserves names starting with "_".
QUERY_PARAMETERS = frozenset({"threshold_deg"})
#: Every counter the service reports, present from the start (at 0).
COUNTERS = (
    "samples_accepted",
    "results_published",
    "results_superseded",
    "deletes_published",
    "frames_published",
    "engagement_published",
    "events_published",
    "queries_answered",
    "queries_refused",
    "publish_errors",
    "tf_lookups_unresolved",
    "ros_published",
)


class _Publishers:
    """Declared publishers, one per output key: a put through one costs a third of a
    session.put (1.2 vs 3.2 us, measured). A body's publisher is undeclared when the body
    is lost, so they never outnumber the bodies tracked (plus the frames)."""

    def __init__(self, session: zenoh.Session) -> None:
        self._session = session
        self._publishers: dict[str, zenoh.Publisher] = {}

    def put(self, key: str, payload: bytes) -> None:
        publisher = self._publishers.get(key)
        if publisher is None:
            publisher = self._session.declare_publisher(
                key, encoding=JSON, congestion_control=zenoh.CongestionControl.BLOCK
            )
            self._publishers[key] = publisher
        publisher.put(payload)

    def forget(self, key: str) -> None:
        if (publisher := self._publishers.pop(key, None)) is not None:
            publisher.undeclare()

    def close(self) -> None:
        for publisher in self._publishers.values():
            publisher.undeclare()
        self._publishers.clear()


@dataclass(frozen=True)
class _QueryItem:
    query: zenoh.Query
    space: str  # which output key space it reached us through: facing, frame, engagement


class _RejectionLog:
    """Summarizes rejections in the log at most every period, with the first offending key
    and detail of each reason seen since the last summary."""

    def __init__(self, clock: Callable[[], float]) -> None:
        self._clock = clock
        self._since_summary: Counter[Rejection] = Counter()
        self._first: dict[Rejection, str] = {}
        self._last_summary = clock()

    def add(self, reason: Rejection, key: str, detail: str) -> None:
        self._since_summary[reason] += 1
        self._first.setdefault(reason, f"{key}: {detail}")

    def next_due(self) -> float | None:
        return self._last_summary + REJECTION_LOG_PERIOD_S if self._since_summary else None

    def maybe_log(self, force: bool = False) -> None:
        """Log the summary when due (or now, with ``force``: at shutdown)."""
        now = self._clock()
        due = force or now >= self._last_summary + REJECTION_LOG_PERIOD_S
        if not (self._since_summary and due):
            return
        parts = ", ".join(
            f"{reason.value}={n} (first: {self._first[reason]})"
            for reason, n in sorted(self._since_summary.items(), key=lambda kv: kv[0].value)
        )
        log.warning(
            "rejected %d samples in the last %.0f s: %s",
            sum(self._since_summary.values()),
            now - self._last_summary,
            parts,
        )
        self._since_summary.clear()
        self._first.clear()
        self._last_summary = now


class FacingService:
    """One running facing service on one zenoh session.

    Use as a context manager, or ``start()`` then ``close()``. ``clock`` is the monotonic
    clock used for staleness; tests may inject their own.
    """

    def __init__(self, settings: Settings, clock: Callable[[], float] = time.monotonic) -> None:
        self.settings = settings
        self._clock = clock
        self._started_at = clock()
        fixed = [] if settings.base_frame == keys.ALL_FRAMES else [settings.base_frame]
        self._tracker = Tracker(
            settings.threshold_deg,
            settings.hysteresis_deg,
            settings.stale_after_s,
            frames=fixed,
            max_bodies=settings.max_bodies,
            engagement=settings.engagement_params(),
            engagement_period_s=settings.engagement_period_s,
            head=settings.head_profile(),
        )
        # ROS 2 input: the robot's people from its TF tree and tracked lists.
        self._wire = Wire(
            RosFormat(settings.ros_format), settings.ros_domain_id, settings.ros_namespace
        )
        self._people = People(settings.ros_base_frame)
        self._ros: Ros2Subscriptions | None = None
        self._ros_out = (
            RosOutput(settings.ros_engagement_rate_hz, settings.ros_intents)
            if settings.output == "ros2"
            else None
        )
        self._inbox: Inbox[tuple[float, object]] = Inbox(INBOX_SIZE)
        self._outbox = Outbox()
        self._closing = threading.Event()
        # Guards what other threads read: counters, rejections, the per-frame snapshot.
        self._counts_lock = threading.Lock()
        self._counts: Counter[str] = Counter(dict.fromkeys(COUNTERS, 0))
        self._rejections: Counter[Rejection] = Counter(dict.fromkeys(Rejection, 0))
        self._tracked: dict[str, int] = self._tracker.tracked_per_frame()
        self._rejection_log = _RejectionLog(clock)
        self._horizon = clock()  # arrival time of the newest item the worker has handled
        self._session: zenoh.Session | None = None
        self._entities: list[zenoh.Subscriber[None] | zenoh.Queryable[None]] = []
        self._token: zenoh.LivelinessToken | None = None
        self._threads: list[threading.Thread] = []

    # -- lifecycle -------------------------------------------------------------------

    def start(self) -> FacingService:
        s = self.settings
        ns, frame = s.namespace, s.base_frame
        self._session = session = zenoh.open(zenoh_config(s))
        try:
            self._publish(Changes(frames=self._tracker.frames()))
            self._threads = [
                threading.Thread(target=self._run, name="facing-worker", daemon=True),
                threading.Thread(target=self._send, name="facing-publisher", daemon=True),
            ]
            for thread in self._threads:
                thread.start()
            body_space, frame_space = keys.result_queryables(ns, frame)
            if s.input == "ros2":
                self._ros = Ros2Subscriptions(session, self._wire, self._enqueue)
                subscription = ", ".join(self._ros.keys)
                inputs = []
            else:
                subscription = keys.pose_subscription(ns, frame)
                inputs = [session.declare_subscriber(subscription, self._enqueue)]
            self._entities = [
                *inputs,
                session.declare_queryable(
                    body_space, lambda q: self._enqueue(_QueryItem(q, "facing"))
                ),
                session.declare_queryable(
                    frame_space, lambda q: self._enqueue(_QueryItem(q, "frame"))
                ),
                session.declare_queryable(
                    keys.engagement_key(ns, keys.ALL_FRAMES, frame),
                    lambda q: self._enqueue(_QueryItem(q, "engagement")),
                ),
                session.declare_queryable(keys.status_key(ns, s.instance), self._on_status),
            ]
            self._token = session.liveliness().declare_token(keys.service_token(ns, s.instance))
        except BaseException:
            self.close()
            raise
        log.info(
            "facing-service %s started: instance %s, zenoh id %s, %s; poses from %s; results "
            "on %s and %s (queryable); status on %s; threshold %.1f deg, hysteresis %.1f deg, "
            "stale after %.1f s, at most %d bodies",
            __version__,
            s.instance,
            session.zid(),
            self._links(),
            subscription,
            body_space,
            frame_space,
            keys.status_key(ns, s.instance),
            s.threshold_deg,
            s.hysteresis_deg,
            s.stale_after_s,
            s.max_bodies,
        )
        return self

    def _links(self) -> str:
        """Mode and endpoints, as the start line says them (no secret: see disclosure)."""
        conf = zenoh_config(self.settings)
        said = {}
        for kind in ("connect", "listen"):
            mode, endpoints = mode_and_endpoints(conf, kind)
            said[kind] = ", ".join(public_endpoint(e) for e in endpoints) or "none"
        return f"mode {mode}, connect {said['connect']}, listen {said['listen']}"

    def close(self) -> None:
        """Stop taking input, stop the threads, close the session. Idempotent.

        Bounded so that SIGTERM exits within 2 s even during a flood (the backlog is
        abandoned) or with a publisher blocked on a stuck consumer (closing the session
        releases it).
        """
        self._closing.set()
        if self._token is not None:
            self._token.undeclare()
            self._token = None
        for entity in self._entities:
            entity.undeclare()
        self._entities = []
        if self._ros is not None:
            self._ros.close()
            self._ros = None
        # Wake an idle worker; a busy one sees the closing flag after its batch.
        self._inbox.wake()
        self._outbox.close()
        for thread in self._threads:
            thread.join(timeout=0.7)
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
        """A consistent snapshot of health, counters and state sizes; thread-safe."""
        # Depth before counters: the publisher counts a publication before reporting it
        # sent, so a depth of 0 read first guarantees the counters below include it all.
        outbox_depth = len(self._outbox)
        with self._counts_lock:
            counts = dict(self._counts)
            rejected = {reason.value: n for reason, n in self._rejections.items()}
            tracked = dict(self._tracked)
        counts["results_superseded"] = self._outbox.superseded
        alive = bool(self._threads) and all(t.is_alive() for t in self._threads)
        return ServiceStatus(
            status="ok" if alive else "failed",
            instance=self.settings.instance,
            version=__version__,
            zenoh_id=str(self._session.zid()) if self._session is not None else "",
            uptime_s=round(self._clock() - self._started_at, 3),
            config=public_settings(self.settings.model_dump(mode="json")),
            bodies_tracked=tracked,
            bodies_tracked_total=sum(tracked.values()),
            counters=counts,
            rejected=rejected,
            connected=self.connected(),
            inbox_depth=len(self._inbox),
            outbox_depth=outbox_depth,
        )

    # -- zenoh callbacks: hand off, nothing else ---------------------------------------

    def _enqueue(self, item: object) -> None:
        self._inbox.put((self._clock(), item), self._closing)  # waits while full

    def _on_status(self, query: zenoh.Query) -> None:
        key = keys.status_key(self.settings.namespace, self.settings.instance)
        query.reply(key, self.status().model_dump_json(), encoding=JSON)
        query.drop()

    # -- worker ----------------------------------------------------------------------

    def _run(self) -> None:
        while not self._closing.is_set():
            batch = self._next_batch()
            try:
                self._handle(batch)
                self._expire()
                self._ros_tick()
                self._rejection_log.maybe_log()
                with self._counts_lock:
                    self._tracked = self._tracker.tracked_per_frame()
            except Exception:  # the worker must outlive any single bug
                log.exception("worker: unexpected error in a batch of %d items", len(batch))
        self._rejection_log.maybe_log(force=True)

    def _next_batch(self) -> list[tuple[float, object]]:
        """What is queued (at most MAX_BATCH), waiting for it until the next deadline."""
        return self._inbox.take(self._idle_timeout(), MAX_BATCH)

    def _idle_timeout(self) -> float | None:
        deadlines = [
            d
            for d in (
                self._tracker.next_expiry(),
                self._tracker.next_due(),
                self._rejection_log.next_due(),
                self._ros_out.next_tick if self._ros_out is not None else None,
            )
            if d is not None
        ]
        if not deadlines:
            return None
        return max(0.0, min(deadlines) - self._clock())

    def _expire(self) -> None:
        """Lose bodies with no sample for ``stale_after_s`` — by arrival time.

        While a backlog waits in the inbox, "now" is the arrival time of the newest item
        handled: a body whose next sample is already queued is not stale, however long
        the worker took to get to it.
        """
        now = self._clock() if not self._inbox else self._horizon
        self._publish(self._tracker.expire(now))
        self._publish(self._tracker.advance(now))

    def _ros_tick(self) -> None:
        """--output ros2: every tracked person's level at hri_engagement's rate."""
        if self._ros_out is not None:
            for message in self._ros_out.tick(self._tracker.engagements(), self._clock()):
                self._outbox.add_ros(message.topic, message.typename, message.payload)

    def _handle(self, batch: list[tuple[float, object]]) -> None:
        """Handle inbox items in order; consecutive poses go to the core together."""
        poses: list[PoseSample] = []
        for arrival, item in batch:
            if isinstance(item, zenoh.Sample):
                self._horizon = arrival
                if item.kind == zenoh.SampleKind.PUT:
                    pose = self._decode(item)
                    if pose is not None:
                        poses.append(pose)
                    continue
                self._flush(poses)
                self._on_delete(str(item.key_expr))
            elif isinstance(item, RosSample):
                self._horizon = arrival
                self._on_ros(item, poses)
            elif isinstance(item, _QueryItem):
                self._flush(poses)
                self._answer(item)
        self._flush(poses)

    def _on_ros(self, sample: RosSample, poses: list[PoseSample]) -> None:
        """A sample of the robot's topics: poses join the batch; losses are published
        after the poses before them, in order."""
        update = route(self._people, self._wire, sample)
        if isinstance(update, Rejected):
            self._reject(update.reason, sample.key, update.detail)
            return
        for reason, what in update.refused:
            self._reject(Rejection(reason), sample.key, what)
        if update.unresolved:
            self._count("tf_lookups_unresolved", update.unresolved)
        poses.extend(update.poses)
        if update.lost:
            self._flush(poses)
            for subject in update.lost:
                self._publish(self._tracker.lose(self._people.base_frame, subject, self._horizon))

    def _decode(self, sample: zenoh.Sample) -> PoseSample | None:
        key = str(sample.key_expr)
        parsed = keys.parse_pose_key(self.settings.namespace, key)
        if parsed is None:
            self._reject(Rejection.INVALID_KEY, key, "not NS/bodies/<id>/pose/<frame>")
            return None
        body_id, frame_id = parsed
        limit = self.settings.max_payload_bytes
        if len(sample.payload) > limit:  # refuse before copying a huge payload
            self._reject(Rejection.PAYLOAD_TOO_LARGE, key, f"{len(sample.payload)} bytes > {limit}")
            return None
        decoded = decode_pose(sample.payload.to_bytes(), body_id, frame_id, limit)
        if isinstance(decoded, Rejected):
            self._reject(decoded.reason, key, decoded.detail)
            return None
        return PoseSample(frame_id, body_id, decoded)

    def _flush(self, poses: list[PoseSample]) -> None:
        """Run the pending poses through the tracker, publish, and empty the list."""
        if not poses:
            return
        changes = self._tracker.ingest(poses, self._horizon)
        ns = self.settings.namespace
        for sample in changes.out_of_order:
            self._reject(
                Rejection.OUT_OF_ORDER,
                keys.pose_key(ns, sample.body_id, sample.frame_id),
                f"stamp {sample.pose.stamp} older than the latest accepted",
            )
        for sample in changes.over_capacity:
            self._reject(
                Rejection.CAPACITY,
                keys.pose_key(ns, sample.body_id, sample.frame_id),
                f"already tracking max_bodies={self.settings.max_bodies}",
            )
        poses.clear()
        self._publish(changes)
        # Counted once handed to the outbox: "all accepted and outbox empty" means all sent.
        self._count("samples_accepted", len(changes.results))

    def _on_delete(self, key: str) -> None:
        parsed = keys.parse_pose_key(self.settings.namespace, key)
        if parsed is None:
            self._reject(Rejection.INVALID_KEY, key, "DELETE on an invalid key")
            return
        body_id, frame_id = parsed
        self._publish(self._tracker.lose(frame_id, body_id, self._horizon))

    def _reject(self, reason: Rejection, key: str, detail: str) -> None:
        with self._counts_lock:
            self._rejections[reason] += 1
        self._rejection_log.add(reason, key, detail)

    def _count(self, name: str, n: int = 1) -> None:
        if n:
            with self._counts_lock:
                self._counts[name] += n

    def _publish(self, changes: Changes) -> None:
        """Hand the publications to the outbox, in the order they must be sent: the worker
        never waits on the network (a stuck consumer only ever stalls the publisher)."""
        ns, me = self.settings.namespace, self.settings.instance
        if changes.results:
            self._outbox.add_results(
                (keys.facing_key(ns, state.body_id, state.frame_id), state.to_json(me))
                for state in changes.results
            )
        for update in changes.engagement:
            if update.level is not Level.UNKNOWN:
                self._outbox.add_change(
                    keys.engagement_key(ns, update.body_id, update.frame_id),
                    _engagement_state(update, me).model_dump_json().encode(),
                    Kind.ENGAGEMENT,
                )
            if update.previous is not None:
                self._outbox.add_change(
                    keys.event_key(ns, update.frame_id),
                    _engagement_event(update, me).model_dump_json().encode(),
                    Kind.EVENT,
                )
        for frame_id, body_id in changes.lost:
            self._outbox.add_delete(keys.facing_key(ns, body_id, frame_id))
            self._outbox.add_delete(keys.engagement_key(ns, body_id, frame_id))
        for frame in changes.frames:
            self._outbox.add_change(
                keys.frame_key(ns, frame.frame_id),
                _mine(frame, me).model_dump_json().encode(),
                Kind.FRAME,
            )
        if self._ros_out is not None:
            for message in self._ros_out.on_changes(changes):
                self._outbox.add_ros(message.topic, message.typename, message.payload)

    def _answer(self, item: _QueryItem) -> None:
        """Reply with the current state of every matching key, one reply per key."""
        query = item.query
        try:
            threshold = _threshold_parameter(query.parameters)
        except ValueError as error:
            query.reply_err(
                QueryError(error="bad_parameter", detail=str(error)).model_dump_json(),
                encoding=JSON,
            )
            query.drop()
            self._count("queries_refused")
            return
        if threshold is None:
            states, frames = self._tracker.states(), self._tracker.frames()
        else:
            states, frames = self._tracker.evaluate(threshold)
        ns, me = self.settings.namespace, self.settings.instance
        if item.space == "facing":
            replies = [(keys.facing_key(ns, s.body_id, s.frame_id), s.to_json(me)) for s in states]
        elif item.space == "frame":
            replies = [
                (keys.frame_key(ns, f.frame_id), _mine(f, me).model_dump_json()) for f in frames
            ]
        else:
            replies = [
                (
                    keys.engagement_key(ns, e.body_id, e.frame_id),
                    _engagement_state(e, me).model_dump_json(),
                )
                for e in self._tracker.engagements()
            ]
        for key, payload in replies:
            if query.key_expr.intersects(zenoh.KeyExpr(key)):
                query.reply(key, payload, encoding=JSON)
        query.drop()
        self._count("queries_answered")

    # -- publisher -------------------------------------------------------------------

    def _send(self) -> None:
        session = self._session
        assert session is not None
        publishers = _Publishers(session)
        ros = None
        if self._ros_out is not None:
            ros = RosPublishers(session, self._wire, self.settings.ros_node_name)
        try:
            while True:
                publications = self._outbox.take()
                if not publications and self._outbox.closed:
                    return
                for p in publications:
                    try:
                        counter = self._send_one(session, publishers, ros, p)
                    except zenoh.ZError:
                        if self._closing.is_set():
                            return  # the session closed under a blocked put: shutting down
                        log.exception("publisher: could not publish on %s", p.key)
                        counter = "publish_errors"
                    with self._counts_lock:
                        self._counts[counter] += 1
                    self._outbox.sent()  # after counting: depth 0 means every count is in
        finally:
            publishers.close()
            if ros is not None:
                ros.close()

    @staticmethod
    def _send_one(
        session: zenoh.Session,
        publishers: _Publishers,
        ros: RosPublishers | None,
        p: Publication,
    ) -> str:
        """Send one publication; returns the name of the counter it counts under."""
        if p.kind is Kind.ROS:  # the robot's own topics (--output ros2)
            assert ros is not None and p.typename is not None
            ros.send(RosMessage(p.key, p.typename, p.payload))
        elif p.kind is Kind.DELETE:  # the body is lost: so is its publisher
            publishers.forget(p.key)
            session.delete(p.key, congestion_control=zenoh.CongestionControl.BLOCK)
        else:
            assert p.payload is not None
            publishers.put(p.key, p.payload)
        return _COUNTER[p.kind]


_COUNTER = {
    Kind.RESULT: "results_published",
    Kind.FRAME: "frames_published",
    Kind.ENGAGEMENT: "engagement_published",
    Kind.EVENT: "events_published",
    Kind.DELETE: "deletes_published",
    Kind.ROS: "ros_published",
}


def _mine(frame: FrameFacing, instance: str) -> FrameFacing:
    return frame.model_copy(update={"instance": instance})


def _engagement_state(update: EngagementUpdate, instance: str) -> EngagementState:
    return EngagementState(
        instance=instance,
        body_id=update.body_id,
        frame_id=update.frame_id,
        stamp=Stamp(sec=update.stamp[0], nanosec=update.stamp[1]),
        level=update.level.name,
        level_value=int(update.level),
        score=update.score,
        zone=update.zone.value,
        since=Stamp(sec=update.since[0], nanosec=update.since[1]),
    )


def _engagement_event(update: EngagementUpdate, instance: str) -> EngagementEvent:
    assert update.previous is not None
    return EngagementEvent(
        instance=instance,
        body_id=update.body_id,
        frame_id=update.frame_id,
        stamp=Stamp(sec=update.stamp[0], nanosec=update.stamp[1]),
        previous=update.previous.name,
        level=update.level.name,
        level_value=int(update.level),
        score=update.score,
        zone=update.zone.value,
    )


def _threshold_parameter(parameters: zenoh.Parameters) -> float | None:
    """The query's ``threshold_deg``, None when absent; ValueError when it is bad."""
    unknown = sorted(
        name for name, _ in parameters if name not in QUERY_PARAMETERS and not name.startswith("_")
    )
    if unknown:
        raise ValueError(
            f"unknown parameter(s) {', '.join(unknown)}; known: "
            f"{', '.join(sorted(QUERY_PARAMETERS))}"
        )
    raw = parameters.get("threshold_deg")
    if raw is None:
        return None
    try:
        value = float(raw)
    except ValueError:
        raise ValueError(f"threshold_deg must be a number, got {raw!r}") from None
    if not (math.isfinite(value) and 0.0 < value < 180.0):
        raise ValueError(f"threshold_deg must be in (0, 180), got {raw!r}")
    return value
