"""The worker: the one thread that owns the tracker. It pulls input samples straight from
zenoh's channel, and queries (and a robot's other topics) from the side queue the
callbacks fill, in arrival order (``intake``); handles them in batches, hands each turn's
publications to the outbox, and answers queries in order with the samples.

Each turn: handle what arrived (the input form reads each sample into poses and losses;
poses go through the core in batches), then what time alone makes due (expiry,
engagement dwell, the scenes and each output's periodic messages, read from one
``TurnSnapshot`` of the tracker, and the input's diagnosis), then hand the publications over.
Each tracker call and its publications are one transaction (``decisions``). A bug met on
an item is counted and logged and that item alone is lost (``internal_error``); the
status says "degraded" until a batch succeeds.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable, Sequence

import zenoh

from ..contract.words import counted
from ..core.records import Changes, PoseSample
from ..core.silence import Change
from ..core.snapshot import TurnSnapshot
from .decisions import Decisions
from .intake import Intake
from .queries import QueryItem

log = logging.getLogger("facing_service")

#: Most intake items handled per batch: bounds the latency a backlog adds to a query.
MAX_BATCH = 1024
#: Wall time a batch may take before the rest of it waits for the next turn of the loop:
#: between turns, what was decided is handed to the publisher, bodies expire, the ROS
#: tick and diagnosis run. Input that is costly to handle (a robot's deep TF chains) then
#: delays the others' results by at most this much, not by the whole batch.
BATCH_BUDGET_S = 0.05


class Worker:
    """The worker's state and its loop (``run``, on the service's worker thread). Every
    attribute is the worker's alone but ``faults.failing`` (read by the status); the
    tracker, the input, the outputs and the scenes are held by its ``Decisions``."""

    def __init__(
        self,
        decisions: Decisions,
        intake: Intake,
        answers: Callable[[QueryItem, TurnSnapshot], None],
        clock: Callable[[], float],
        closing: threading.Event,
    ) -> None:
        self._decisions = decisions
        self.silence = decisions.silence  # (core.silence) its fields are read by the
        # status, written here alone
        self._ledger = decisions.ledger
        self.faults = decisions.faults  # its ``failing`` is read by the status
        self._intake = intake
        self._answers = answers
        self._clock = clock
        self._closing = closing
        self._ledger.tracked = decisions.tracker.tracked_per_frame()
        self._horizon = clock()  # when the worker took what it handles now
        self._drained = True  # the last take emptied the intake
        self._carried: list[object] = []  # the rest of a batch over BATCH_BUDGET_S

    def first_aggregates(self) -> None:
        """Every declared frame's aggregate, before any input (sent once the publisher
        starts): a consumer learns the frame exists, with nobody in it yet."""
        self._decisions.publish(Changes(frames=self._decisions.tracker.frames()))
        self._decisions.to_outbox()

    def run(self) -> None:
        """The worker thread's loop, until the service closes."""
        while not self._closing.is_set():
            try:
                batch = self._next_batch()
            except zenoh.ZError:  # the channel closed: shutting down
                break
            self.turn(batch)
        self._ledger.rejection_log.maybe_log(force=True)

    def turn(self, batch: Sequence[object]) -> None:
        """One turn of the loop over what was taken (also driven alone by
        benchmarks.perf.hot_path, to measure it without the network)."""
        try:
            self._handle(batch)
            self._expire()
            self._time_tick(TurnSnapshot(self._decisions.tracker, self._decisions.scenes))
            self._decisions.source.diagnose()
            self._ledger.rejection_log.maybe_log()
            self._ledger.tracked = self._decisions.tracker.tracked_per_frame()
            self._decisions.to_outbox()
        except Exception as error:  # the worker must outlive any single bug, and say so
            self.faults.caught(error, f"a batch of {len(batch)} items")
        self.faults.end_turn(bool(batch))

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
        """When time alone makes the worker's next change (the clock's time), if ever.
        While a silent input's people are held, no level moves with time alone."""
        tracker, silence = self._decisions.tracker, self.silence
        held = silence.holding
        return min(
            (
                d
                for d in (
                    tracker.next_expiry(silence.staleness_s(self._horizon)),
                    None if held else tracker.next_due(),
                    silence.next_due(len(tracker) > 0),
                    self._ledger.rejection_log.next_due(),
                    self._decisions.source.next_due(),
                    self._decisions.scenes.next_due(),
                    *(output.next_due() for output in self._decisions.outputs),
                )
                if d is not None
            ),
            default=None,
        )

    def _expire(self) -> None:
        """Lose bodies with no sample for the staleness in force (``core.silence``:
        ``--stale-after-s`` while the input is heard, up to ``--hold-silent-s`` while it
        is silent), and log what the input's silence did.

        "Now" is when the worker took what it just handled: a body whose next sample was
        already queued is not stale, however long the worker took to get to it, and a
        batch slower than the staleness does not make the bodies it updated stale. Nor
        does the rest of a batch over its budget: expiry waits until it is handled.
        """
        if self._carried:  # taken at the horizon, not handled yet: they may refresh bodies
            return
        tracker, silence, now = self._decisions.tracker, self.silence, self._horizon
        change = silence.look(now, len(tracker) > 0)
        people = counted(len(tracker), "person", "people")
        if change is Change.SILENT:
            log.warning(
                "the input is silent: nothing heard for %.1f s with %s tracked; holding them "
                "as they were for up to %g s after their own last pose (--hold-silent-s): "
                "a link or a tracker stalled",
                now - (silence.last_heard or now), people, silence.params.hold_s,
            )  # fmt: skip
        elif change is Change.SLOW:
            log.warning(
                "the input arrives about every %.1f s, no faster than --silent-after-s "
                "(%g s): each pause between its messages holds its people as a silence "
                "would, and a person whose poses stop is lost when the input is heard "
                "without them; set --silent-after-s (and --stale-after-s) above its period "
                "to tell a stalled link from its rate (logged once)",
                silence.period_s or 0.0, silence.params.after_s,
            )  # fmt: skip
        staleness = silence.staleness_s(now)
        for call in tracker.timed(now, staleness, advancing=not silence.holding):
            changes = self._decisions.apply(call)
            if changes.lost and staleness > silence.params.stale_s and silence.first_losses():
                log.warning(
                    "the input has been silent for %.1f s: people not heard for %g s "
                    "(--hold-silent-s) are lost: %d now, %d still held until each passes it",
                    now - (silence.last_heard or now), staleness, len(changes.lost),
                    len(tracker),
                )  # fmt: skip

    def _heard(self) -> None:
        """Something whole came from the input (refused samples are not it speaking);
        the end of a silence that was logged is logged too."""
        if self.silence.heard(self._horizon) is Change.BACK:
            log.warning(
                "the input is back after %.1f s of silence; %s tracked",
                self.silence.ended_s,
                counted(len(self._decisions.tracker), "person", "people"),
            )

    def _time_tick(self, snapshot: TurnSnapshot) -> None:
        """What time alone makes due, read from the turn's snapshot: each frame whose people
        changed (at most ``--group-rate-hz``: who faces whom and its groups, said when
        they changed), then each output's periodic messages."""
        for update in self._decisions.scenes.tick(self._clock(), snapshot):
            for output in self._decisions.outputs:
                self._decisions.add(output.on_scene(update))
            if update.left_out:
                self._ledger.count("scene_people_left_out", update.left_out)
        now = self._clock()
        for output in self._decisions.outputs:  # (most turns: none due, and our JSON keys never)
            if (due := output.next_due()) is not None and due <= now:
                self._decisions.add(output.tick(now, snapshot))

    def _handle(self, batch: Sequence[object]) -> None:
        """Handle the items in order; consecutive poses go to the core together. An item
        that meets a bug is counted and skipped: the others are handled. Past
        BATCH_BUDGET_S the rest waits for the next turn (see ``_next_batch``)."""
        poses: list[PoseSample] = []
        source = self._decisions.source
        read_whole = source.read_whole
        deadline = time.monotonic() + BATCH_BUDGET_S
        for i, item in enumerate(batch):
            if self._closing.is_set():  # SIGTERM under a flood: the backlog is abandoned
                return
            if i and time.monotonic() > deadline:
                self._carried = list(batch[i:])
                break
            try:
                self._handle_one(item, poses)
            except Exception as error:
                self.faults.caught(error, f"an input item ({type(item).__name__})")
        self._decisions.flush(poses, self._horizon)
        if source.read_whole != read_whole:
            self._heard()

    def _handle_one(self, item: object, poses: list[PoseSample]) -> None:
        if isinstance(item, QueryItem):
            self._decisions.flush(poses, self._horizon)
            # What was decided before the query goes out (and is counted) first: a status
            # read after the answer agrees with it, as a result sent before it does.
            self._decisions.to_outbox()
            snapshot = TurnSnapshot(self._decisions.tracker, self._decisions.scenes)
            self._ledger.tracked = snapshot.tracked  # the status then agrees with the answer
            self._answers(item, snapshot)
        elif (loss := self._decisions.source.read(item, poses)) is not None:
            self._decisions.flush(poses, self._horizon)  # the poses before it first
            self._decisions.lose(loss, self._horizon)
