"""The zenoh shell: subscribe to poses, run the core, publish results, answer queries.

Threads, and why:
- the worker: owns the tracker. Pulls input samples straight from zenoh's channel, and
  queries (and a robot's other topics) from the side queue the callbacks fill, in arrival
  order (see ``intake``); handles them in batches, hands publications to the outbox,
  answers queries in order with the samples. Bounded: when the channel is full zenoh's
  receive thread waits, which pushes back to the senders (trackers publishing with BLOCK
  slow down; nothing is dropped here).
- zenoh callbacks (queries, a robot's other topics): only queue the item for the worker.
  A slow callback would stall every subscriber of the session.
- the alarm (``intake``): wakes a waiting worker at its next deadline.
- the publisher (``publisher``): sends what the outbox holds, with BLOCK. A slow consumer
  slows it down; one that stops reading blocks it (up to zenoh's ``wait_before_close``).
  Only this thread waits, while the worker keeps ingesting, deciding and answering.
- the status queryable answers from the ledger in its callback, so a health check gets an
  answer even when the worker is behind a backlog.

What is said is built by pure functions (``publications``); what is counted, and how it is
read consistently, lives in ``ledger``.

Congestion control (docs/contract.md): every output is BLOCK and sent by the publisher
thread only, so nothing is dropped silently. A slow consumer slows everything down (the
worker waits for room in the outbox); per-body results are superseded (counted) only
when the publisher has moved nothing for 0.5 s, and aggregates and DELETEs never are.
(DROP for per-body results lost 2.5 % of a 100 000-pose burst to a consumer that was
merely slower than the burst, and made nothing faster; see benchmarks.)
"""

from __future__ import annotations

import logging
import os
import sys
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial

import zenoh

from .. import __version__
from ..config.disclosure import public_endpoint, public_settings, zenoh_failure
from ..config.settings import Settings, effective_session, mode_and_endpoints, zenoh_config
from ..contract import keys
from ..contract.keys import BodyRef
from ..contract.schemas import (
    QueryError,
    Rejected,
    Rejection,
    Ros2Status,
    ServiceStatus,
    decode_pose,
)
from ..core.tracker import Changes, PoseSample, Tracker
from ..ros2.diagnosis import RobotWatch
from ..ros2.input import Ros2Subscriptions, RosSample, reading, route
from ..ros2.output import RosOutput, RosPublishers
from ..ros2.people import People
from ..ros2.types import TF_MESSAGE
from ..ros2.wire import FormLearner
from .intake import Intake
from .ledger import Ledger
from .outbox import Outbox, Publication
from .publications import publications, query_replies, ros_publications, threshold_parameter
from .publisher import JSON, Publisher
from .threads import daemon_thread

log = logging.getLogger("facing_service")

#: ROS 2 input: how often the worker checks why people may give no results (ros2_diagnosis).
DIAGNOSIS_PERIOD_S = 1.0
#: ROS 2 input, until /tf arrives where expected: /tf on any other key (another domain,
#: namespace, format or type hash), to say where the robot's data went.
STRAY_TF_KEYS = ("**/tf", "**/tf/tf2_msgs::msg::dds_::TFMessage_/*")

#: Most inbox items handled per batch: bounds the latency a backlog adds to a query.
MAX_BATCH = 1024
#: Wall time a batch may take before the rest of it waits for the next turn of the loop:
#: between turns, what was decided is handed to the publisher, bodies expire, the ROS
#: tick and diagnosis run. Input that is dear to handle (a robot's deep TF chains) then
#: delays the others' results by at most this much, not by the whole batch.
BATCH_BUDGET_S = 0.05
#: ROS 2 input: the topic read from zenoh's channel by the worker (the others stream far
#: less, and come through callbacks).
HOT_ROS_TOPIC = ("/tf", TF_MESSAGE)
#: Intake bound before zenoh pushes back. Queued zenoh samples hold native memory: under a
#: sustained flood (python -m benchmarks.soak) an 8192-deep inbox let the service's RSS
#: climb to a ~350 MB plateau; 1024 keeps it flat (~134 MB with 10 000 bodies tracked) at
#: the same throughput, since batches are at most MAX_BATCH anyway.
INBOX_SIZE = 1024


@dataclass(frozen=True)
class _QueryItem:
    query: zenoh.Query
    space: str  # which output key space it reached us through: facing, frame, engagement


def tracker_for(settings: Settings) -> Tracker:
    """The tracker a service with these settings runs (also the offline evaluation's, in
    benchmarks.crossval: the same decisions without the network)."""
    fixed = [] if settings.base_frame == keys.ALL_FRAMES else [settings.base_frame]
    return Tracker(
        settings.threshold_deg,
        settings.hysteresis_deg,
        settings.stale_after_s,
        frames=fixed,
        max_bodies=settings.max_bodies,
        engagement=settings.engagement_params(),
        engagement_period_s=settings.engagement_period_s,
        head=settings.head_profile(),
    )


class FacingService:
    """One running facing service on one zenoh session.

    Use as a context manager, or ``start()`` then ``close()``. ``clock`` is the monotonic
    clock used for staleness; tests may inject their own.
    """

    def __init__(self, settings: Settings, clock: Callable[[], float] = time.monotonic) -> None:
        self.settings = settings
        self._clock = clock
        self._started_at = clock()
        self._tracker = tracker_for(settings)
        # ROS 2 input: the robot's people from its TF tree and tracked lists.
        self._wire = settings.ros_wire()
        self._form = FormLearner(settings.forced_distro)
        self._people = People(
            settings.ros_base_frame,
            max_ids=settings.max_bodies,
            max_frames=settings.ros_max_frames,
        )
        self._ros: Ros2Subscriptions | None = None
        self._watch = RobotWatch(self._wire, clock())
        self._findings: dict[str, str] = {}  # replaced whole by the worker
        self._strays: deque[str] = deque(maxlen=64)  # filled by the stray /tf callbacks
        self._sniffers: list[zenoh.Subscriber[None]] = []
        self._next_diagnosis: float | None = None  # ROS 2 input only
        self._ros_out = (
            RosOutput(settings.ros_engagement_rate_hz, settings.ros_intents)
            if settings.output == "ros2"
            else None
        )
        self._pose_key = keys.PoseKeyParser(settings.namespace, 2 * settings.max_bodies)
        self._intake: Intake | None = None
        self._outbox = Outbox()
        self._closing = threading.Event()
        self._ledger = Ledger(clock)
        self._said: list[Publication] = []  # decided this turn of the worker's loop
        self._accepted = 0  # samples whose results are in _said
        self._ledger.tracked = self._tracker.tracked_per_frame()
        self._horizon = clock()  # when the worker took what it handles now
        self._drained = True  # the last take emptied the intake
        self._session: zenoh.Session | None = None
        self._entities: list[zenoh.Subscriber[None] | zenoh.Queryable[None]] = []
        self._token: zenoh.LivelinessToken | None = None
        self._threads: list[threading.Thread] = []
        self._session_said: dict[str, object] = {}  # mode and scouting in force (status)
        self._failing = False  # the worker's last batch raised (written by the worker only)
        self._faults = 0  # errors in the current batch (the worker's)
        self._carried: list[object] = []  # the rest of a batch over BATCH_BUDGET_S

    # -- lifecycle -------------------------------------------------------------------

    def start(self) -> FacingService:
        s = self.settings
        ns, frame = s.namespace, s.base_frame
        conf = zenoh_config(s)
        self._session_said = effective_session(s, conf)
        self._session = session = zenoh.open(conf)
        try:
            self._publish(Changes(frames=self._tracker.frames()))
            self._hand_over()
            ros = None
            if self._ros_out is not None:
                ros = partial(RosPublishers, session, self._wire, s.ros_node_name, self._form)
            publisher = Publisher(session, self._outbox, self._ledger, self._closing, ros)
            self._threads = [
                daemon_thread(self._run, "facing-worker"),
                daemon_thread(publisher.run, "facing-publish"),
            ]
            if s.input == "ros2":  # the hot topic is /tf; the others come by callbacks
                hot = self._wire.subscription(*HOT_ROS_TOPIC, any_type=True)
                self._intake = Intake(session, hot, INBOX_SIZE, self._closing, self._clock)
                self._ros = Ros2Subscriptions(
                    session, self._wire, self._enqueue, HOT_ROS_TOPIC, s.ros_max_message_bytes
                )
                subscription = ", ".join([hot, *self._ros.keys])
                self._sniffers = [
                    session.declare_subscriber(
                        k,
                        lambda s: self._strays.append(str(s.key_expr)),
                        allowed_origin=zenoh.Locality.REMOTE,  # not the intake's wake-ups
                    )
                    for k in STRAY_TF_KEYS
                ]
                self._next_diagnosis = self._clock() + DIAGNOSIS_PERIOD_S
            else:
                subscription = keys.pose_subscription(ns, frame)
                self._intake = Intake(session, subscription, INBOX_SIZE, self._closing, self._clock)
            for thread in self._threads:
                thread.start()
            body_space, frame_space = keys.result_queryables(ns, frame)
            self._entities = [
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
            "stale after %.1f s, at most %d bodies%s",
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
            self._ros_said(),
        )
        return self

    def _ros_said(self) -> str:
        """The ROS 2 part of the start line: what is read, how faces are judged, what is
        answered on the robot's topics."""
        s = self.settings
        said = ""
        if s.input == "ros2":
            wire = self._wire
            where = f"domain {wire.domain_id}, " if wire.format.value == "rmw_zenoh" else ""
            ns = f"namespace '{wire.namespace}'" if wire.namespace else "no namespace"
            head = s.head_profile()
            said += (
                f"; ROS 2 input in {wire.format.value} format ({where}{ns}), people looked up "
                f"in {s.ros_base_frame}, faces facing within {head.threshold_deg:.1f} deg "
                f"({s.head_cone})"
            )
        if s.output == "ros2":
            topics = "engagement_status, facing lists" + (", /intents" if s.ros_intents else "")
            said += f"; ROS 2 output on the robot's topics ({topics})"
        return said

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
        self._stop_sniffing()
        if self._intake is not None:  # a waiting worker wakes; a busy one sees the flag
            self._intake.close()
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
        alive = bool(self._threads) and all(t.is_alive() for t in self._threads)
        health = "failed" if not alive else "degraded" if self._failing else "ok"
        return self._ledger.status(
            self._outbox,
            status=health,
            instance=self.settings.instance,
            version=__version__,
            zenoh_id=str(self._session.zid()) if self._session is not None else "",
            uptime_s=round(self._clock() - self._started_at, 3),
            config=public_settings(self.settings.model_dump(mode="json") | self._session_said),
            connected=self.connected(),
            inbox_depth=len(self._intake) if self._intake is not None else 0,
            ros2=self._ros2_status(),
        )

    def _ros2_status(self) -> Ros2Status | None:
        if self.settings.input != "ros2":
            return None
        form = self._form.current
        return Ros2Status(
            format=self._wire.format.value,
            distro=form.distro.value,
            attachment=form.attachment.value,
            form_from=self._form.source,
            findings=self._findings,
        )

    # -- zenoh callbacks: hand off, nothing else ---------------------------------------

    def _enqueue(self, item: object) -> None:
        assert self._intake is not None
        self._intake.put(item)  # waits while full

    def _on_status(self, query: zenoh.Query) -> None:
        key = keys.status_key(self.settings.namespace, self.settings.instance)
        query.reply(key, self.status().model_dump_json(), encoding=JSON)
        query.drop()

    # -- worker ----------------------------------------------------------------------

    def _run(self) -> None:
        while not self._closing.is_set():
            try:
                batch = self._next_batch()
            except zenoh.ZError:  # the channel closed: shutting down
                break
            self._faults = 0
            try:
                self._handle(batch)
                self._expire()
                self._ros_tick()
                self._diagnose()
                self._ledger.rejection_log.maybe_log()
                self._ledger.tracked = self._tracker.tracked_per_frame()
                self._hand_over()
            except Exception as error:  # the worker must outlive any single bug, and say so
                self._fault(error, f"a batch of {len(batch)} items")
            if batch or self._faults:  # "degraded" until a batch succeeds: a turn woken
                self._failing = self._faults > 0  # by the alarm alone proves nothing
        self._ledger.rejection_log.maybe_log(force=True)

    def _fault(self, error: Exception, where: str) -> None:
        """A bug met in the worker: counted, logged (the first of a batch with its
        traceback), and the status says "degraded" until a batch has none."""
        self._ledger.count("worker_errors")
        self._faults += 1
        if self._faults == 1:
            log.error("worker: unexpected error in %s", where, exc_info=error)

    def _next_batch(self) -> list[object]:
        """What arrived (at most MAX_BATCH), waiting for it until the next deadline
        (worked out only when the last take emptied the intake: otherwise there is no
        wait, and it is the loop's dearest step). The rest of a batch over its budget
        comes first, at the time it was taken (``_horizon``)."""
        assert self._intake is not None
        if self._carried:
            batch, self._carried = self._carried, []
            return batch
        if self._drained:
            self._intake.set_alarm(self._next_deadline())
        batch, self._drained = self._intake.take(MAX_BATCH)
        self._horizon = self._clock()
        return batch

    def _next_deadline(self) -> float | None:
        """When time alone makes the worker's next change (the clock's time), if ever."""
        return min(
            (
                d
                for d in (
                    self._tracker.next_expiry(),
                    self._tracker.next_due(),
                    self._ledger.rejection_log.next_due(),
                    self._ros_out.next_tick if self._ros_out is not None else None,
                    self._next_diagnosis,
                )
                if d is not None
            ),
            default=None,
        )

    def _expire(self) -> None:
        """Lose bodies with no sample for ``stale_after_s``.

        "Now" is when the worker took what it just handled: a body whose next sample was
        already queued is not stale, however long the worker took to get to it, and a
        batch slower than ``stale_after_s`` does not make the bodies it updated stale. Nor
        does the rest of a batch over its budget: expiry waits until it is handled.
        """
        if self._carried:  # taken at the horizon, not handled yet: they may refresh bodies
            return
        for call in self._tracker.timed(self._horizon):
            self._apply(call)

    def _ros_tick(self) -> None:
        """--output ros2: every tracked person's level at hri_engagement's rate."""
        if self._ros_out is not None:
            messages = self._ros_out.tick(self._tracker.engagements, self._clock())
            self._said += ros_publications(messages)

    def _diagnose(self) -> None:
        """--input ros2, every DIAGNOSIS_PERIOD_S: why people may give no results. Each
        finding is logged once when it appears and once when it clears; the status shows
        the current ones."""
        now = self._clock()
        if self._next_diagnosis is None or now < self._next_diagnosis:
            return
        self._next_diagnosis = now + DIAGNOSIS_PERIOD_S
        while self._strays:
            key = self._strays.popleft()
            if isinstance(reading(self._wire, key), Rejected):  # not where /tf is read
                self._watch.on_stray(key)
        if self._watch.topics.get("/tf"):
            self._stop_sniffing()  # /tf arrives where expected: strays no longer matter
        findings = self._watch.findings(self._people, now)
        for code, line in findings.items():
            if code not in self._findings:
                log.warning("ROS 2 input: %s [%s]", line, code)
        for code in self._findings.keys() - findings.keys():
            log.info("ROS 2 input: %s no longer holds", code)
        self._findings = findings

    def _stop_sniffing(self) -> None:
        for sniffer in self._sniffers:
            sniffer.undeclare()
        self._sniffers = []

    def _handle(self, batch: list[object]) -> None:
        """Handle the items in order; consecutive poses go to the core together. An item
        that meets a bug is counted and skipped: the others are handled. Past
        BATCH_BUDGET_S the rest waits for the next turn (see ``_next_batch``)."""
        poses: list[PoseSample] = []
        deadline = time.monotonic() + BATCH_BUDGET_S
        for i, item in enumerate(batch):
            if self._closing.is_set():  # SIGTERM under a flood: the backlog is abandoned
                return
            if i and time.monotonic() > deadline:
                self._carried = batch[i:]
                break
            try:
                self._handle_one(item, poses)
            except Exception as error:
                self._fault(error, f"an input item ({type(item).__name__})")
        self._flush(poses)

    def _handle_one(self, item: object, poses: list[PoseSample]) -> None:
        if isinstance(item, zenoh.Sample):
            if self._ros is not None:  # the robot's /tf, from the intake's channel
                if item.kind == zenoh.SampleKind.PUT:
                    self._on_ros(RosSample.of(item, self.settings.ros_max_message_bytes), poses)
            elif item.kind == zenoh.SampleKind.PUT:
                pose = self._decode(item)
                if pose is not None:
                    poses.append(pose)
            else:
                self._flush(poses)
                self._on_delete(str(item.key_expr))
        elif isinstance(item, RosSample):
            self._on_ros(item, poses)
        elif isinstance(item, _QueryItem):
            self._flush(poses)
            self._answer(item)

    def _on_ros(self, sample: RosSample, poses: list[PoseSample]) -> None:
        """A sample of the robot's topics: poses join the batch; losses are published
        after the poses before them, in order."""
        if (learned := self._form.learn(sample.key, sample.attachment)) is not None:
            log.log(learned[0], "%s", learned[1])
        update = route(self._people, self._wire, sample, self.settings.ros_max_message_bytes)
        if isinstance(update, Rejected):
            self._reject(update.reason, sample.key, update.detail)
            return
        self._watch.on_input(reading(self._wire, sample.key)[0])  # type: ignore[index]
        if update.time_back_ns:
            self._watch.time_back = (self._clock(), update.time_back_ns)
            self._next_diagnosis = self._clock()  # said at once
        for reason, what in update.refused:
            self._reject(Rejection(reason), sample.key, what)
        if update.unresolved:
            self._ledger.count("tf_lookups_unresolved", update.unresolved)
        poses.extend(update.poses)
        if update.lost:
            self._flush(poses)
            base, back = self._people.base_frame, update.time_back_ns > 0
            bodies = [BodyRef(frame_id=base, body_id=subject) for subject in update.lost]
            self._apply(lambda: self._tracker.lose(bodies, self._horizon, time_went_back=back))

    def _decode(self, sample: zenoh.Sample) -> PoseSample | None:
        key = str(sample.key_expr)
        parsed = self._pose_key(key)
        if parsed is None:
            self._reject(Rejection.INVALID_KEY, key, "not NS/bodies/<id>/pose/<frame>")
            return None
        limit = self.settings.max_payload_bytes
        if len(sample.payload) > limit:  # refuse before copying a huge payload
            self._reject(Rejection.PAYLOAD_TOO_LARGE, key, f"{len(sample.payload)} bytes > {limit}")
            return None
        decoded = decode_pose(sample.payload.to_bytes(), parsed.body_id, parsed.frame_id, limit)
        if isinstance(decoded, Rejected):
            self._reject(decoded.reason, key, decoded.detail)
            return None
        return PoseSample(parsed, decoded)

    def _flush(self, poses: list[PoseSample]) -> None:
        """Run the pending poses through the tracker, publish, and empty the list. When
        that meets a bug, the poses go again one by one: only the one at fault is lost
        (refused as internal_error), never the batch's others."""
        if not poses:
            return
        batch = list(poses)
        poses.clear()
        try:
            self._ingest(batch)
            return
        except Exception as error:
            self._fault(error, f"a batch of {len(batch)} poses")
            if len(batch) == 1:
                self._refuse(batch[0], error)
                return
        for sample in batch:
            try:
                self._ingest([sample])
            except Exception as error:
                self._fault(error, f"the pose of {sample.body_id} in {sample.frame_id}")
                self._refuse(sample, error)

    def _refuse(self, sample: PoseSample, error: Exception) -> None:
        """A pose whose handling met a bug: refused alone, as internal_error."""
        detail = f"{type(error).__name__}: {error}"
        self._reject(Rejection.INTERNAL_ERROR, self._input_of(sample), detail)

    def _ingest(self, poses: list[PoseSample]) -> None:
        changes = self._apply(lambda: self._tracker.ingest(poses, self._horizon))
        for sample in changes.out_of_order:
            self._reject(
                Rejection.OUT_OF_ORDER,
                self._input_of(sample),
                f"stamp {sample.pose.stamp} older than the latest accepted",
            )
        for sample in changes.over_capacity:
            self._reject(
                Rejection.CAPACITY,
                self._input_of(sample),
                f"already tracking max_bodies={self.settings.max_bodies}",
            )
        self._accepted += len(changes.results)

    def _input_of(self, sample: PoseSample) -> str:
        """Where a pose came from, as its sender names it: the pose key of the JSON input,
        the TF lookup on the ROS 2 input (whose wire has no pose keys)."""
        if self._ros is None:
            return keys.pose_key(self.settings.namespace, sample.body_id, sample.frame_id)
        frame = self._people.frame_of(sample.body_id) or "?"
        return f"/tf {sample.frame_id} -> {frame} ({sample.body_id})"

    def _apply(self, change: Callable[[], Changes]) -> Changes:
        """One tracker call and the publications it calls for, whole or not at all: when
        either raises, the tracker is as before and nothing of it is said."""
        said = len(self._said)
        try:
            with self._tracker.transaction():
                changes = change()
                self._publish(changes)
        except Exception:
            del self._said[said:]
            raise
        return changes

    def _on_delete(self, key: str) -> None:
        parsed = self._pose_key(key)
        if parsed is None:
            self._reject(Rejection.INVALID_KEY, key, "DELETE on an invalid key")
            return
        self._apply(lambda: self._tracker.lose(parsed, self._horizon))

    def _reject(self, reason: Rejection, key: str, detail: str) -> None:
        self._ledger.reject(reason, key, detail)

    def _publish(self, changes: Changes) -> None:
        """What the changes call for, in the order it must be sent (handed over at the end
        of the loop's turn, see ``_hand_over``)."""
        self._said += publications(changes, self.settings.namespace, self.settings.instance)
        if self._ros_out is not None:
            self._said += ros_publications(self._ros_out.on_changes(changes))

    def _hand_over(self) -> None:
        """Give the publisher all this turn decided, in one go, as the worker is about to
        wait: one lock and one wake-up per turn, and the publisher wakes when the worker
        lets go of the GIL rather than waiting for it. The worker never waits on the
        network (a stuck consumer only ever stalls the publisher).

        Accepted samples are counted once their results are handed over: "all accepted and
        the outbox empty" means all sent."""
        if self._said:
            self._outbox.add(self._said)
            self._said = []
        if self._accepted:
            self._ledger.count("samples_accepted", self._accepted)
            self._accepted = 0

    def _answer(self, item: _QueryItem) -> None:
        """Reply with the current state of every matching key, one reply per key."""
        query = item.query
        try:
            threshold = threshold_parameter(dict(query.parameters))
        except ValueError as error:
            query.reply_err(
                QueryError(error="bad_parameter", detail=str(error)).model_dump_json(),
                encoding=JSON,
            )
            query.drop()
            self._ledger.count("queries_refused")
            return
        # The status then agrees with the answer (a client reading it next sees the same).
        self._ledger.tracked = self._tracker.tracked_per_frame()
        if threshold is None:
            states, frames = self._tracker.states(), self._tracker.frames()
        else:
            states, frames = self._tracker.evaluate(threshold)
        engagements = self._tracker.engagements() if item.space == "engagement" else []
        ns, me = self.settings.namespace, self.settings.instance
        for key, payload in query_replies(item.space, ns, me, states, frames, engagements):
            if query.key_expr.intersects(zenoh.KeyExpr(key)):
                query.reply(key, payload, encoding=JSON)
        query.drop()
        self._ledger.count("queries_answered")


def run_until(settings: Settings, stop: threading.Event) -> int:
    """``facing-service run``: the service until ``stop``; the process's exit code."""
    service = FacingService(settings)
    failure: list[zenoh.ZError] = []
    opened = threading.Event()

    def start() -> None:
        try:
            service.start()
        except zenoh.ZError as error:
            failure.append(error)
        finally:
            opened.set()

    # zenoh.open can wait indefinitely (a client with connect/timeout_ms:-1 waits for its
    # router) inside native code, where Python never runs signal handlers; so it runs on a
    # helper thread and this one stays responsive to SIGTERM and Ctrl-C.
    threading.Thread(target=start, name="facing-open", daemon=True).start()
    if not wait_until_open(opened, settings, stop):  # nothing is open yet, nothing to close
        log.info("stopped before zenoh connected")
        logging.shutdown()
        os._exit(0)  # the helper thread is stuck in zenoh.open; do not wait for it
    if failure:
        print(zenoh_failure("run", failure[0]), file=sys.stderr)
        return 1
    try:
        warn_while_unreachable(service, settings, stop)
    finally:
        service.close()
    log.info("stopped")
    return 0


#: How often ``run`` says that its connect endpoints are still unreachable.
UNREACHABLE_WARNING_S = 10.0


def wait_until_open(opened: threading.Event, settings: Settings, stop: threading.Event) -> bool:
    """True once zenoh.open has returned, False if ``stop`` came first. A client told to
    wait for its router (``connect/timeout_ms: -1``, as compose.yaml sets) waits inside
    zenoh.open, where zenoh says nothing: this says it, every UNREACHABLE_WARNING_S."""
    next_warning = time.monotonic() + UNREACHABLE_WARNING_S
    while not opened.wait(0.1):
        if stop.is_set():
            return False
        if time.monotonic() >= next_warning:
            next_warning += UNREACHABLE_WARNING_S
            log.warning(
                "still waiting for a router at %s before the session opens (zenoh keeps "
                "trying); nothing is read or published meanwhile",
                ", ".join(public_endpoint(e) for e in settings.connect) or "any endpoint",
            )
    return True


def warn_while_unreachable(
    service: FacingService, settings: Settings, stop: threading.Event
) -> None:
    """Until ``stop``: zenoh retries unreachable endpoints forever and says nothing, so
    ``run`` says it, every UNREACHABLE_WARNING_S while the session has nobody."""
    while not stop.wait(UNREACHABLE_WARNING_S):
        links = service.connected()
        if settings.connect and not (links["routers"] or links["peers"]):
            log.warning(
                "no router or peer reachable at %s yet (zenoh keeps trying); results reach "
                "nobody meanwhile",
                ", ".join(public_endpoint(e) for e in settings.connect),
            )
