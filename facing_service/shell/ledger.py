"""What the service counts, and the one rule for reading it consistently.

Every counter has exactly one writer: the worker counts what it decided (samples accepted,
queries, rejections, unresolved lookups) and the publisher counts what it sent. So no
counter needs a lock: under the GIL a ``+=`` by the only writer cannot lose an update, and
a reader copies each dict in one step (all keys exist from the start, so a copy never
races a resize). The rule a reader needs: read the outbox depth *before* the counters. The
publisher counts a publication before reporting it sent, so a depth of 0 read first
guarantees the counters read after include everything the worker put in the outbox.

Rejections are also summarized in the log, at most every ``REJECTION_LOG_PERIOD_S``, never
one line per sample.
"""

from __future__ import annotations

import logging
from collections import Counter
from collections.abc import Callable
from typing import Any

from ..contract.keys import cut
from ..contract.poses import Rejection
from ..contract.schemas import ServiceStatus
from ..contract.words import counted
from .outbox import Kind, Outbox, Publication

log = logging.getLogger("facing_service")

#: Rejections are summarized in the log at most this often, never one line per sample.
REJECTION_LOG_PERIOD_S = 5.0
#: How much of the first offending key and detail the summary quotes: both can come from
#: a sender (a 1 MB frame name made a 3 MB log line).
FIRST_SAID = 300
#: The worker's counters (it is their only writer).
DECIDED = (
    "samples_accepted",
    "queries_answered",
    "queries_refused",
    "tf_lookups_unresolved",
    "worker_errors",
    "scene_people_left_out",
    "clock_restarts",
)
#: The publisher's counters, one per kind of publication, plus its errors.
SENT = {
    Kind.RESULT: "results_published",
    Kind.FRAME: "frames_published",
    Kind.ENGAGEMENT: "engagement_published",
    Kind.EVENT: "events_published",
    Kind.ROS: "ros_published",
    Kind.SCENE: "scene_published",
}
#: A body lost: the DELETEs of its result and engagement keys, counted apart.
LOST = "deletes_published"
_BODY_KEYS = frozenset({Kind.RESULT, Kind.ENGAGEMENT})
PUBLISH_ERRORS = "publish_errors"
#: Every counter the service reports, present from the start (at 0), in this order.
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
    "scene_published",
    "scene_people_left_out",
    "clock_restarts",
    "worker_errors",
)


class RejectionLog:
    """Summarizes rejections in the log at most every period, with the first offending key
    and detail of each reason seen since the last summary: a WARNING, or INFO when every
    one of them was harmless (counted all the same, but nothing for an operator to do)."""

    def __init__(self, clock: Callable[[], float]) -> None:
        self._clock = clock
        self._since_summary: Counter[Rejection] = Counter()
        self._first: dict[Rejection, str] = {}
        self._last_summary = clock()
        self._first_at = self._last_summary  # when the first rejection of a summary came
        self._worrying = 0  # rejections since the summary that were not harmless

    def add(self, reason: Rejection, key: str, detail: str, harmless: bool = False) -> None:
        if not self._since_summary:
            self._first_at = self._clock()
        self._since_summary[reason] += 1
        self._worrying += not harmless
        if reason not in self._first:
            self._first[reason] = cut(f"{key}: {detail}", FIRST_SAID)

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
        log.log(
            logging.WARNING if self._worrying else logging.INFO,
            "rejected %s in the last %.0f s: %s",
            counted(sum(self._since_summary.values()), "sample", "samples"),
            max(now - self._first_at, 1.0),  # since the first of them (since the
            parts,  # last summary, minutes before the first, was said)
        )
        self._since_summary.clear()
        self._first.clear()
        self._worrying = 0
        self._last_summary = now


class Ledger:
    """The service's counters, rejections and tracked-bodies snapshot, and its status."""

    def __init__(self, clock: Callable[[], float]) -> None:
        self.decided = dict.fromkeys(DECIDED, 0)  # written by the worker only
        self.sent = dict.fromkeys((*SENT.values(), LOST, PUBLISH_ERRORS), 0)  # the publisher only
        self.rejected = dict.fromkeys(Rejection, 0)  # the worker only
        self.tracked: dict[str, int] = {}  # replaced whole by the worker, never mutated
        self.rejection_log = RejectionLog(clock)

    # -- the worker's side ---------------------------------------------------------------

    def reject(self, reason: Rejection, key: str, detail: str, harmless: bool = False) -> None:
        self.rejected[reason] += 1
        self.rejection_log.add(reason, key, detail, harmless)

    def count(self, name: str, n: int = 1) -> None:
        self.decided[name] += n

    # -- the publisher's side ------------------------------------------------------------

    def count_sent(self, publication: Publication | None) -> None:
        """One publication sent, or failed to send (None)."""
        if publication is None:
            counter = PUBLISH_ERRORS
        elif publication.payload is None and publication.kind in _BODY_KEYS:
            counter = LOST
        else:
            counter = SENT[publication.kind]
        self.sent[counter] += 1

    # -- readers (any thread) ------------------------------------------------------------

    def status(self, outbox: Outbox, **identity: Any) -> ServiceStatus:
        """A consistent snapshot: counters, rejections and sizes, plus ``identity`` (the
        fields of ``ServiceStatus`` the service itself knows: instance, version, ...)."""
        outbox_depth = len(outbox)  # first: see the module docstring
        counts = dict(self.decided) | dict(self.sent)
        counts["results_superseded"] = outbox.superseded
        tracked = self.tracked
        return ServiceStatus(
            **identity,
            bodies_tracked=tracked,
            bodies_tracked_total=sum(tracked.values()),
            counters={name: counts[name] for name in COUNTERS},
            rejected={reason.value: n for reason, n in dict(self.rejected).items()},
            outbox_depth=outbox_depth,
        )
