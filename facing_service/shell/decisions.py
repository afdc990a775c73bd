"""What the worker decides, and how a bug in it stays small.

``Decisions``: each tracker call and the publications it calls for, in one transaction
(whole or not at all: when either raises, the tracker is as before and nothing of it is
said); the turn's publications, handed to the outbox in one go; poses that meet a bug
tried again one by one, so only the one at fault is lost (``internal_error``).
``Faults``: the bugs met in a turn, counted and logged, and the status's "degraded".
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass

from ..contract.keys import BodyRef
from ..contract.poses import Rejection
from ..core.records import Changes, PoseSample
from ..core.silence import InputSilence
from ..core.social.scene import Scenes
from ..core.tracker import RESTART_EVIDENCE, Tracker
from .inputs import Input, Loss
from .ledger import Ledger
from .outbox import Outbox, Publication
from .outputs import Output

log = logging.getLogger("facing_service")


class Faults:
    """``failing`` is read by the status (any thread); the rest is the worker's."""

    def __init__(self, ledger: Ledger) -> None:
        self._ledger = ledger
        self.failing = False  # the last batch raised
        self.in_turn = 0  # errors in the current turn

    def caught(self, error: Exception, where: str) -> None:
        """A bug caught in the worker: counted, logged (the first of a turn with its
        traceback), and the status says "degraded" until a batch has none: from before
        the count, so a status that shows the error also says degraded."""
        self.failing = True
        self._ledger.count("worker_errors")
        self.in_turn += 1
        if self.in_turn == 1:
            log.error("worker: unexpected error in %s", where, exc_info=error)

    def end_turn(self, handled_any: bool) -> None:
        """ "degraded" until a batch succeeds: a turn woken by the alarm alone proves nothing."""
        if handled_any or self.in_turn:
            self.failing = self.in_turn > 0
        self.in_turn = 0


@dataclass(frozen=True)
class Parts:
    """What the worker's decisions are made with (``compose.parts_for`` makes them from
    the settings): the tracker, the scenes, the input and the outputs, and whether the
    input is heard (its silence)."""

    tracker: Tracker
    scenes: Scenes
    source: Input
    outputs: Sequence[Output]
    silence: InputSilence


class Decisions:
    """The one owner of the worker's collaborators (``tracker``, ``source``, ``outputs``,
    ``scenes``: the worker reads them here), and of what a turn decided."""

    def __init__(self, parts: Parts, ledger: Ledger, outbox: Outbox) -> None:
        self.tracker = parts.tracker
        self.source = parts.source
        self.outputs = parts.outputs
        self.scenes = parts.scenes
        self.silence = parts.silence
        self.ledger = ledger
        self._outbox = outbox
        self.faults = Faults(ledger)  # its ``failing`` is read by the status
        self._decided: list[Publication] = []  # decided this turn of the loop
        self._accepted = 0  # samples whose results are in _decided

    def add(self, publications: list[Publication]) -> None:
        """Publications decided outside a tracker call (scenes, periodic messages)."""
        self._decided += publications

    def apply(self, change: Callable[[], Changes]) -> Changes:
        """One tracker call and the publications it calls for, whole or not at all."""
        with self._whole():
            changes = change()
            self.publish(changes)
        return changes

    @contextmanager
    def _whole(self) -> Iterator[None]:
        """Tracker calls and their publications, whole or not at all."""
        mark = len(self._decided)
        try:
            with self.tracker.transaction():
                yield
        except Exception:
            del self._decided[mark:]
            raise

    def publish(self, changes: Changes) -> None:
        """What the changes call for, in the order it must be sent (put in the outbox at the end
        of the loop's turn, see ``to_outbox``); the frames they touch are due a scene."""
        for output in self.outputs:
            self._decided += output.on_changes(changes)
        if changes.lost:
            self.source.forget(changes.lost)
        if changes.results or changes.lost:
            self.scenes.touch(
                {s.frame_id for s in changes.results} | {b.frame_id for b in changes.lost}
            )

    def lose(self, loss: Loss, now: float) -> None:
        self.apply(lambda: self.tracker.lose(loss.bodies, now, time_went_back=loss.time_went_back))

    def flush(self, poses: list[PoseSample], now: float) -> None:
        """Run the pending poses through the tracker, publish, and empty the list. When
        that meets a bug, the poses go again one by one: only the one at fault is lost
        (refused as internal_error), never the batch's others. One bug is one error: the
        pose that meets it alone, or the batch when none does."""
        if not poses:
            return
        batch = list(poses)
        poses.clear()
        try:
            self._ingest(batch, now)
            return
        except Exception as error:
            batch_error = error
        culprits = 0
        for sample in batch:
            try:
                self._ingest([sample], now)
            except Exception as error:
                culprits += 1
                self.faults.caught(error, f"the pose of {sample.body_id} in {sample.frame_id}")
                self._refuse(sample, error)
        if not culprits:  # met together only: each alone went through
            self.faults.caught(batch_error, f"a batch of {len(batch)} poses")

    def _refuse(self, sample: PoseSample, error: Exception) -> None:
        detail = f"{type(error).__name__}: {error}"
        self.ledger.reject(Rejection.INTERNAL_ERROR, self.source.origin(sample), detail)

    def _ingest(self, poses: list[PoseSample], now: float) -> None:
        """The poses, and those of trackers whose clock started over (a new life: lost,
        then followed on the new clock), in one transaction; what they decided is counted
        once it holds. Before, the restart's part ran after the first part was
        counted and kept: a bug in it had ``flush`` go over every pose again, counting the
        first part twice and refusing its poses as out of order."""
        steps: list[Changes] = []
        restarted: list[list[BodyRef]] = []
        with self._whole():
            batch = poses
            while batch:
                steps.append(changes := self.tracker.ingest(batch, now))
                self.publish(changes)
                batch = changes.restarted
                if batch:
                    restarted.append(list(dict.fromkeys(sample.body for sample in batch)))
                    self.publish(self.tracker.lose(restarted[-1], now, time_went_back=True))
        for changes in steps:
            self._count(changes)
        for bodies in restarted:
            for body in bodies:
                log.warning(
                    "%s in %s: its tracker's clock started over (%d poses in a row older "
                    "than its last, each newer than the one before): lost, and followed "
                    "on the new clock", body.body_id, body.frame_id, RESTART_EVIDENCE,
                )  # fmt: skip
            self.ledger.count("clock_restarts", len(bodies))

    def _count(self, changes: Changes) -> None:
        for sample in changes.out_of_order:
            self.ledger.reject(
                Rejection.OUT_OF_ORDER,
                self.source.origin(sample),
                f"stamp {sample.pose.stamp} older than the latest accepted",
            )
        for sample in changes.over_capacity:
            self.ledger.reject(
                Rejection.CAPACITY,
                self.source.origin(sample),
                f"already tracking max_bodies={self.tracker.max_bodies}",
            )
        self._accepted += len(changes.results)

    def to_outbox(self) -> None:
        """Give the publisher all this turn decided, in one go, as the worker is about to
        wait: one lock and one wake-up per turn, and the publisher wakes when the worker
        lets go of the GIL rather than waiting for it. The worker never waits on the
        network (a stuck consumer only ever stalls the publisher).

        Accepted samples are counted once their results are in the outbox: "all accepted and
        the outbox empty" means all sent."""
        if self._decided:
            self._outbox.add(self._decided)
            self._decided = []
        if self._accepted:
            self.ledger.count("samples_accepted", self._accepted)
            self._accepted = 0
