"""The worker: the one thread that owns the tracker. It pulls input samples straight from
zenoh's channel, and queries (and a robot's other topics) from the side queue the
callbacks fill, in arrival order (``intake``); handles them in batches, hands each turn's
publications to the outbox, and answers queries in order with the samples.

Each turn: handle what arrived (poses in batches through the core, each tracker call and
its publications in one transaction), then what time alone makes due (expiry, engagement
dwell, the ROS 2 tick and diagnosis), then hand the publications over. A bug met on an
item is counted and logged and that item alone is lost (``internal_error``); the status
says "degraded" until a batch succeeds.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable, Sequence

import zenoh

from ..config.profiles import scene_params
from ..config.settings import Settings
from ..contract.poses import Rejection
from ..core.records import Changes, PoseSample
from ..core.scene import Scenes
from ..core.tracker import Tracker
from ..core.view import TurnView
from .inputs import Input
from .intake import Intake
from .ledger import Ledger
from .outbox import Outbox, Publication
from .outputs import Output
from .queries import QueryItem, answer

log = logging.getLogger("facing_service")

#: Most inbox items handled per batch: bounds the latency a backlog adds to a query.
MAX_BATCH = 1024
#: Wall time a batch may take before the rest of it waits for the next turn of the loop:
#: between turns, what was decided is handed to the publisher, bodies expire, the ROS
#: tick and diagnosis run. Input that is costly to handle (a robot's deep TF chains) then
#: delays the others' results by at most this much, not by the whole batch.
BATCH_BUDGET_S = 0.05


class Worker:
    """The worker's state and its loop (``run``, on the service's worker thread). Every
    attribute is the worker's alone but ``failing`` (read by the status) and ``intake``
    (set by the service once its session is open)."""

    def __init__(
        self,
        settings: Settings,
        clock: Callable[[], float],
        tracker: Tracker,
        source: Input,
        outputs: Sequence[Output],
        ledger: Ledger,
        outbox: Outbox,
        intake: Intake,
        closing: threading.Event,
    ) -> None:
        self._clock = clock
        self._tracker = tracker
        self._input = source
        self._outputs = outputs
        self._ledger = ledger
        self._outbox = outbox
        self._intake = intake
        self._closing = closing
        self._settings = settings  # for the queries' answers and the capacity's reason
        self._decided: list[Publication] = []  # decided this turn of the loop
        self._accepted = 0  # samples whose results are in _decided
        self._ledger.tracked = self._tracker.tracked_per_frame()
        self._horizon = clock()  # when the worker took what it handles now
        self._drained = True  # the last take emptied the intake
        self.failing = False  # the last batch raised (written by the worker only)
        self._faults = 0  # errors in the current batch
        self._carried: list[object] = []  # the rest of a batch over BATCH_BUDGET_S
        self._scenes = Scenes(scene_params(settings))

    def first_aggregates(self) -> None:
        """Every declared frame's aggregate, before any input (sent once the publisher
        starts): a consumer learns the frame exists, with nobody in it yet."""
        self._publish(Changes(frames=self._tracker.frames()))
        self._hand_over()

    def run(self) -> None:
        """The worker thread's loop, until the service closes."""
        while not self._closing.is_set():
            try:
                batch = self._next_batch()
            except zenoh.ZError:  # the channel closed: shutting down
                break
            self._faults = 0
            try:
                self._handle(batch)
                self._expire()
                self._time_tick(TurnView(self._tracker))
                self._input.diagnose()
                self._ledger.rejection_log.maybe_log()
                self._ledger.tracked = self._tracker.tracked_per_frame()
                self._hand_over()
            except Exception as error:  # the worker must outlive any single bug, and say so
                self._fault(error, f"a batch of {len(batch)} items")
            if batch or self._faults:  # "degraded" until a batch succeeds: a turn woken
                self.failing = self._faults > 0  # by the alarm alone proves nothing
        self._ledger.rejection_log.maybe_log(force=True)

    def _fault(self, error: Exception, where: str) -> None:
        """A bug met in the worker: counted, logged (the first of a batch with its
        traceback), and the status says "degraded" until a batch has none: from before
        the count, so a status that shows the error also says degraded."""
        self.failing = True
        self._ledger.count("worker_errors")
        self._faults += 1
        if self._faults == 1:
            log.error("worker: unexpected error in %s", where, exc_info=error)

    def _next_batch(self) -> list[object]:
        """What arrived (at most MAX_BATCH), waiting for it until the next deadline
        (worked out only when the last take emptied the intake: otherwise there is no
        wait, and it is the loop's dearest step). The rest of a batch over its budget
        comes first, at the time it was taken (``_horizon``)."""
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
                    self._input.next_due(),
                    self._scenes.next_due(),
                    *(output.next_due() for output in self._outputs),
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

    def _time_tick(self, view: TurnView) -> None:
        """What time alone makes due, read from the turn's view: each frame whose people
        changed (at most ``--group-rate-hz``: who faces whom and its groups, said when
        they changed), then each output's periodic messages."""
        for update in self._scenes.tick(self._clock(), view):
            for output in self._outputs:
                self._decided += output.on_scene(update)
            if update.left_out:
                self._ledger.count("scene_people_left_out", update.left_out)
        now, current = self._clock(), self._scenes.current()
        for output in self._outputs:
            self._decided += output.tick(now, view, current)

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
        if isinstance(item, QueryItem):
            self._flush(poses)
            # What was decided before the query goes out (and is counted) first: a status
            # read after the answer agrees with it, as a result sent before it does.
            self._hand_over()
            answer(item, self._tracker, self._scenes, self._ledger, self._settings)
        elif (loss := self._input.read(item, poses)) is not None:
            self._flush(poses)  # the poses before it first, in order
            self._apply(
                lambda: self._tracker.lose(loss.bodies, self._horizon,
                                           time_went_back=loss.time_went_back)
            )  # fmt: skip

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
        self._reject(Rejection.INTERNAL_ERROR, self._input.origin(sample), detail)

    def _ingest(self, poses: list[PoseSample]) -> None:
        changes = self._apply(lambda: self._tracker.ingest(poses, self._horizon))
        for sample in changes.out_of_order:
            self._reject(
                Rejection.OUT_OF_ORDER,
                self._input.origin(sample),
                f"stamp {sample.pose.stamp} older than the latest accepted",
            )
        for sample in changes.over_capacity:
            self._reject(
                Rejection.CAPACITY,
                self._input.origin(sample),
                f"already tracking max_bodies={self._settings.max_bodies}",
            )
        self._accepted += len(changes.results)

    def _apply(self, change: Callable[[], Changes]) -> Changes:
        """One tracker call and the publications it calls for, whole or not at all: when
        either raises, the tracker is as before and nothing of it is said."""
        mark = len(self._decided)
        try:
            with self._tracker.transaction():
                changes = change()
                self._publish(changes)
        except Exception:
            del self._decided[mark:]
            raise
        return changes

    def _reject(self, reason: Rejection, key: str, detail: str) -> None:
        self._ledger.reject(reason, key, detail)

    def _publish(self, changes: Changes) -> None:
        """What the changes call for, in the order it must be sent (handed over at the end
        of the loop's turn, see ``_hand_over``)."""
        for output in self._outputs:
            self._decided += output.on_changes(changes)
        if changes.results or changes.lost:
            self._scenes.touch(
                {s.frame_id for s in changes.results} | {b.frame_id for b in changes.lost}
            )

    def _hand_over(self) -> None:
        """Give the publisher all this turn decided, in one go, as the worker is about to
        wait: one lock and one wake-up per turn, and the publisher wakes when the worker
        lets go of the GIL rather than waiting for it. The worker never waits on the
        network (a stuck consumer only ever stalls the publisher).

        Accepted samples are counted once their results are handed over: "all accepted and
        the outbox empty" means all sent."""
        if self._decided:
            self._outbox.add(self._decided)
            self._decided = []
        if self._accepted:
            self._ledger.count("samples_accepted", self._accepted)
            self._accepted = 0
