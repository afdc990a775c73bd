"""Counters, rejections and the status snapshot: one writer each, one reading rule; the
rejection log's rate limit."""

from __future__ import annotations

import logging

from facing_service.contract.poses import Rejection
from facing_service.shell.ledger import COUNTERS, REJECTION_LOG_PERIOD_S, Ledger
from facing_service.shell.outbox import Kind, Outbox, Publication

IDENTITY = {
    "status": "ok",
    "instance": "i",
    "version": "0",
    "zenoh_id": "z",
    "uptime_s": 1.0,
    "config": {},
    "connected": {},
    "inbox_depth": 0,
}


class Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def test_every_counter_and_reason_is_reported_from_the_start():
    status = Ledger(Clock()).status(Outbox(), **IDENTITY)
    assert list(status.counters) == list(COUNTERS)
    assert set(status.counters.values()) == {0}
    assert status.rejected == dict.fromkeys((r.value for r in Rejection), 0)


def test_what_each_side_counts_lands_under_its_name():
    ledger = Ledger(Clock())
    ledger.count("samples_accepted", 3)
    ledger.count("queries_answered")
    ledger.reject(Rejection.SCHEMA, "hri/bodies/a/pose/cam", "x: missing")
    sent = [
        Publication("hri/bodies/a/facing/cam", b"{}", Kind.RESULT),
        Publication("hri/bodies/b/facing/cam", b"{}", Kind.RESULT),
        Publication("hri/bodies/a/facing/cam", None, Kind.RESULT),  # a lost: a DELETE
        Publication("/humans/bodies/tracked", b"\0", Kind.ROS),
        None,  # failed
    ]
    for publication in sent:
        ledger.count_sent(publication)
    ledger.tracked = {"cam": 2, "map": 1}
    status = ledger.status(Outbox(), **IDENTITY)
    counted = {k: v for k, v in status.counters.items() if v}
    assert counted == {
        "samples_accepted": 3,
        "queries_answered": 1,
        "results_published": 2,
        "deletes_published": 1,
        "ros_published": 1,
        "publish_errors": 1,
    }
    assert status.rejected["schema"] == 1
    assert (status.bodies_tracked, status.bodies_tracked_total) == ({"cam": 2, "map": 1}, 3)


def test_the_outbox_depth_is_read_before_the_counters():
    """A publication sent while the status is taken is either still in the depth or
    already in the counters: never in neither (the consistency rule health checks use)."""
    ledger = Ledger(Clock())

    class SendsWhileMeasured(Outbox):
        def __len__(self) -> int:
            ledger.count_sent(Publication("r", b"{}", Kind.RESULT))  # right after the read
            return 0

    status = ledger.status(SendsWhileMeasured(), **IDENTITY)
    assert status.outbox_depth == 0
    assert status.counters["results_published"] == 1


def test_rejections_are_summarized_at_most_once_per_period(caplog):
    clock = Clock()
    ledger = Ledger(clock)
    caplog.set_level(logging.WARNING, logger="facing_service")
    for i in range(1000):
        ledger.reject(Rejection.SCHEMA, f"hri/bodies/b{i}/pose/cam", "header: Field required")
    ledger.reject(Rejection.OUT_OF_ORDER, "hri/bodies/a/pose/cam", "stamp (1, 0) older")
    assert ledger.rejection_log.next_due() == 100.0 + REJECTION_LOG_PERIOD_S
    clock.now += REJECTION_LOG_PERIOD_S - 0.01
    ledger.rejection_log.maybe_log()
    assert caplog.records == []  # not yet due: 1001 rejections, no line
    clock.now += 0.01
    ledger.rejection_log.maybe_log()
    (line,) = [r.getMessage() for r in caplog.records]
    assert line.startswith("rejected 1001 samples in the last 5 s: ")
    assert "out_of_order=1 (first: hri/bodies/a/pose/cam: stamp (1, 0) older)" in line
    assert "schema=1000 (first: hri/bodies/b0/pose/cam: header: Field required)" in line
    ledger.rejection_log.maybe_log()
    assert len(caplog.records) == 1 and ledger.rejection_log.next_due() is None
    # the next window starts at the summary; a shutdown flushes it early
    ledger.reject(Rejection.CAPACITY, "hri/bodies/z/pose/cam", "full")
    clock.now += 1.0
    ledger.rejection_log.maybe_log()
    assert len(caplog.records) == 1
    ledger.rejection_log.maybe_log(force=True)
    assert caplog.records[-1].getMessage() == (
        "rejected 1 sample in the last 1 s: capacity=1 (first: hri/bodies/z/pose/cam: full)"
    )
    # a defect found: "in the last 255 s" was the time since the last summary, not since the
    # first rejection it counts
    clock.now += 250.0
    ledger.reject(Rejection.CAPACITY, "hri/bodies/z/pose/cam", "full")
    clock.now += REJECTION_LOG_PERIOD_S
    ledger.rejection_log.maybe_log()
    assert caplog.records[-1].getMessage().startswith("rejected 1 sample in the last 5 s: ")
    # the counters keep every rejection whatever the log said
    assert ledger.status(Outbox(), **IDENTITY).rejected["schema"] == 1000


def test_a_summary_of_harmless_rejections_only_is_info_not_a_warning(caplog):
    """Every replay of the shared two-person recording began with a WARNING about a
    /tf_static transform refused, which the line itself called harmless."""
    clock = Clock()
    ledger = Ledger(clock)
    caplog.set_level(logging.INFO, logger="facing_service")
    ledger.reject(Rejection.TF_OLD_DATA, "/tf_static", "a -> b (harmless)", harmless=True)
    ledger.rejection_log.maybe_log(force=True)
    ledger.reject(Rejection.TF_OLD_DATA, "/tf_static", "a -> b (harmless)", harmless=True)
    ledger.reject(Rejection.SCHEMA, "hri/bodies/a/pose/cam", "header: Field required")
    ledger.rejection_log.maybe_log(force=True)
    assert [r.levelno for r in caplog.records] == [logging.INFO, logging.WARNING]
    assert ledger.status(Outbox(), **IDENTITY).rejected["tf_old_data"] == 2  # counted all


def test_the_status_schema_names_every_counter_in_order():
    """ServiceStatus.counters' description is what a consumer reads: it lists them all."""
    from facing_service.contract.schemas import ServiceStatus

    description = ServiceStatus.model_fields["counters"].description or ""
    named = [c for c in description.replace(":", ",").split(", ") if c.strip() in COUNTERS]
    assert named == list(COUNTERS)


def test_a_summary_quotes_a_huge_key_cut(caplog):
    """A 1 MB frame name made a 3 MB log line."""
    ledger = Ledger(Clock())
    caplog.set_level(logging.WARNING, logger="facing_service")
    ledger.reject(Rejection.TF_NAN, "0/tf/x/y", "map -> " + "x" * 1_000_000)
    ledger.rejection_log.maybe_log(force=True)
    (line,) = [r.getMessage() for r in caplog.records]
    assert len(line) < 500 and "(1000017 chars)" in line
