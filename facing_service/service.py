"""The zenoh shell: subscribe to poses, run the core, publish results, answer queries.

Threading: zenoh runs each Python callback on its own thread fed by a small queue, and a
slow callback stalls every subscriber of the session. So the callbacks here only append
the sample or query to an inbox; a single worker thread owns the tracker, drains the inbox
in batches (one vectorized core call per batch), publishes, and answers queries. Queries
therefore see exactly the state left by every sample received before them, with no lock
around the state.

Congestion control per key (see the README):
- per-body results ``NS/bodies/<id>/facing/<frame>`` (PUT): DROP. Each result supersedes
  the previous one for that body; a consumer too slow to read them must not stall the
  service. What it would miss is never a membership change: those travel on
- per-frame aggregates ``NS/facing/<frame>`` and per-body DELETEs: BLOCK, so state
  changes are never silently dropped under load.
"""

from __future__ import annotations

import logging
import math
import queue
import threading
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass

import zenoh

from . import __version__, keys
from .config import Settings, zenoh_config
from .schemas import QueryError, Rejected, Rejection, decode_pose
from .tracker import Changes, PoseSample, Tracker

log = logging.getLogger("facing_service")

JSON = zenoh.Encoding.APPLICATION_JSON
#: Most inbox items handled per batch: bounds the latency a huge backlog adds to a query.
MAX_BATCH = 1024
#: Rejections are summarized in the log at most this often, never one line per sample.
REJECTION_LOG_PERIOD_S = 5.0
#: Selector parameters the queryable understands; zenoh reserves names starting with "_".
QUERY_PARAMETERS = frozenset({"threshold_deg"})

#: Every counter the service reports, present from the start (at 0).
COUNTERS = (
    "samples_accepted",
    "results_published",
    "deletes_published",
    "frames_published",
    "queries_answered",
    "queries_refused",
)

_STOP = object()


@dataclass(frozen=True)
class _QueryItem:
    query: zenoh.Query
    per_body: bool  # which output key space the query reached us through


class _RejectionLog:
    """Counts rejections per reason; logs a summary at most every period, with the first
    offending key and detail of each reason seen since the last summary."""

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
        fixed = [] if settings.base_frame == keys.ALL_FRAMES else [settings.base_frame]
        self._tracker = Tracker(
            settings.threshold_deg, settings.hysteresis_deg, settings.stale_after_s, fixed
        )
        self._inbox: queue.SimpleQueue[object] = queue.SimpleQueue()
        self._counts_lock = threading.Lock()
        self._counts: Counter[str] = Counter(dict.fromkeys(COUNTERS, 0))
        self._rejections: Counter[Rejection] = Counter()
        self._rejection_log = _RejectionLog(clock)
        self._session: zenoh.Session | None = None
        self._entities: list[zenoh.Subscriber[None] | zenoh.Queryable[None]] = []
        self._worker: threading.Thread | None = None

    # -- lifecycle -------------------------------------------------------------------

    def start(self) -> FacingService:
        ns, frame = self.settings.namespace, self.settings.base_frame
        self._session = session = zenoh.open(zenoh_config(self.settings))
        try:
            self._publish(Changes(frames=self._tracker.frames()))
            self._worker = threading.Thread(
                target=self._run, name="facing-service-worker", daemon=True
            )
            self._worker.start()
            subscription = keys.pose_subscription(ns, frame)
            body_space, frame_space = keys.result_queryables(ns, frame)
            self._entities = [
                session.declare_subscriber(subscription, self._inbox.put),
                session.declare_queryable(
                    body_space, lambda q: self._inbox.put(_QueryItem(q, per_body=True))
                ),
                session.declare_queryable(
                    frame_space, lambda q: self._inbox.put(_QueryItem(q, per_body=False))
                ),
            ]
        except BaseException:
            self.close()
            raise
        log.info(
            "facing-service %s started: zenoh id %s; poses from %s; results on %s and %s "
            "(queryable); threshold %.1f deg, hysteresis %.1f deg, stale after %.1f s",
            __version__,
            session.zid(),
            subscription,
            body_space,
            frame_space,
            self.settings.threshold_deg,
            self.settings.hysteresis_deg,
            self.settings.stale_after_s,
        )
        return self

    def close(self) -> None:
        """Stop taking input, stop the worker, close the session. Idempotent."""
        for entity in self._entities:
            entity.undeclare()
        self._entities = []
        if self._worker is not None:
            self._inbox.put(_STOP)
            # Bounded so SIGTERM exits within 2 s even if the worker is blocked in a BLOCK
            # put to a stuck consumer: closing the session below releases that put.
            self._worker.join(timeout=1.0)
            self._worker = None
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

    def counters(self) -> dict[str, object]:
        """A consistent snapshot of what the service has done so far."""
        with self._counts_lock:
            return {
                **self._counts,
                "rejected": {r.value: n for r, n in self._rejections.items()},
            }

    # -- worker ----------------------------------------------------------------------

    def _run(self) -> None:
        while True:
            batch = self._next_batch()
            try:
                if self._handle(batch):
                    return
                self._publish(self._tracker.expire(self._clock()))
                self._rejection_log.maybe_log()
            except Exception:  # the worker must outlive any single bug
                log.exception("worker: unexpected error in a batch of %d items", len(batch))
                if any(item is _STOP for item in batch):
                    return

    def _next_batch(self) -> list[object]:
        """Wait for the first item (or the next deadline), then take what is queued."""
        try:
            batch = [self._inbox.get(timeout=self._idle_timeout())]
        except queue.Empty:
            return []
        while len(batch) < MAX_BATCH:
            try:
                batch.append(self._inbox.get_nowait())
            except queue.Empty:
                break
        return batch

    def _idle_timeout(self) -> float | None:
        deadlines = [
            d
            for d in (self._tracker.next_expiry(), self._rejection_log.next_due())
            if d is not None
        ]
        if not deadlines:
            return None
        return max(0.0, min(deadlines) - self._clock())

    def _handle(self, batch: list[object]) -> bool:
        """Handle inbox items in order; consecutive poses go to the core together."""
        poses: list[PoseSample] = []
        for item in batch:
            if isinstance(item, zenoh.Sample):
                if item.kind == zenoh.SampleKind.PUT:
                    pose = self._decode(item)
                    if pose is not None:
                        poses.append(pose)
                    continue
                self._flush(poses)
                self._on_delete(str(item.key_expr))
            elif isinstance(item, _QueryItem):
                self._flush(poses)
                self._answer(item)
            elif item is _STOP:
                self._flush(poses)
                self._rejection_log.maybe_log(force=True)
                return True
        self._flush(poses)
        return False

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
        changes = self._tracker.ingest(poses, self._clock())
        for sample in changes.out_of_order:
            self._reject(
                Rejection.OUT_OF_ORDER,
                keys.pose_key(self.settings.namespace, sample.body_id, sample.frame_id),
                f"stamp {sample.pose.stamp} older than the latest accepted",
            )
        poses.clear()
        self._count("samples_accepted", len(changes.results))
        self._publish(changes)

    def _on_delete(self, key: str) -> None:
        parsed = keys.parse_pose_key(self.settings.namespace, key)
        if parsed is None:
            self._reject(Rejection.INVALID_KEY, key, "DELETE on an invalid key")
            return
        body_id, frame_id = parsed
        self._publish(self._tracker.lose(frame_id, body_id))

    def _reject(self, reason: Rejection, key: str, detail: str) -> None:
        with self._counts_lock:
            self._rejections[reason] += 1
        self._rejection_log.add(reason, key, detail)

    def _count(self, name: str, n: int = 1) -> None:
        if n:
            with self._counts_lock:
                self._counts[name] += n

    # -- output ----------------------------------------------------------------------

    def _publish(self, changes: Changes) -> None:
        session = self._session
        assert session is not None
        ns = self.settings.namespace
        for state in changes.results:
            session.put(
                keys.facing_key(ns, state.body_id, state.frame_id),
                state.model_dump_json(),
                encoding=JSON,
                congestion_control=zenoh.CongestionControl.DROP,
            )
        for frame_id, body_id in changes.lost:
            session.delete(
                keys.facing_key(ns, body_id, frame_id),
                congestion_control=zenoh.CongestionControl.BLOCK,
            )
        for frame in changes.frames:
            session.put(
                keys.frame_key(ns, frame.frame_id),
                frame.model_dump_json(),
                encoding=JSON,
                congestion_control=zenoh.CongestionControl.BLOCK,
            )
        self._count("results_published", len(changes.results))
        self._count("deletes_published", len(changes.lost))
        self._count("frames_published", len(changes.frames))

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
        ns = self.settings.namespace
        if item.per_body:
            replies = [
                (keys.facing_key(ns, s.body_id, s.frame_id), s.model_dump_json()) for s in states
            ]
        else:
            replies = [(keys.frame_key(ns, f.frame_id), f.model_dump_json()) for f in frames]
        for key, payload in replies:
            if query.key_expr.intersects(zenoh.KeyExpr(key)):
                query.reply(key, payload, encoding=JSON)
        query.drop()
        self._count("queries_answered")


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
