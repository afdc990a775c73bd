"""A tracker call and its publications are one transaction: a bug met on one pose of a
batch loses that pose alone (refused as internal_error), with the tracker rolled back and
nothing of it said; the others go through, in order."""

from __future__ import annotations

import logging
import time

from facing_service.config.profiles import scene_params
from facing_service.config.settings import Settings
from facing_service.contract.poses import Rejection
from facing_service.core.records import Changes
from facing_service.core.social.scene import Scenes
from facing_service.shell.compose import silence_for
from facing_service.shell.decisions import Decisions, Faults, Parts
from facing_service.shell.inputs import JsonInput
from facing_service.shell.ledger import Ledger
from facing_service.shell.outbox import Kind, Outbox, Publication
from facing_service.shell.outputs import JsonOutput

from trackers import sample, tracker


class FailsOnBob(JsonOutput):
    """Our JSON output with a bug for one body (the kind of bug the transaction is for)."""

    def on_changes(self, changes: Changes) -> list[Publication]:
        if any(state.body_id == "bob" for state in changes.results):
            raise RuntimeError("a bug for bob")
        return super().on_changes(changes)


def decisions_with(output: JsonOutput) -> tuple[Decisions, Ledger, Outbox, Faults]:
    settings = Settings(base_frame="cam")
    ledger, outbox = Ledger(time.monotonic), Outbox()
    source = JsonInput("hri", "cam", 65536, settings.max_bodies, ledger)
    parts = Parts(
        tracker(), Scenes(scene_params(settings)), source, [output], silence_for(settings)
    )
    made = Decisions(parts, ledger, outbox)
    return made, ledger, outbox, made.faults


def test_a_bug_on_one_pose_loses_that_pose_alone(caplog):
    caplog.set_level(logging.ERROR, logger="facing_service")
    made, ledger, outbox, faults = decisions_with(FailsOnBob("hri", "test", 100))
    poses = [sample("ann", sec=1), sample("bob", sec=1), sample("cat", sec=1)]
    made.flush(poses, 0.0)
    made.to_outbox()
    said = outbox.take(0)
    results = [p.key for p in said if p.kind is Kind.RESULT]
    assert results == ["hri/bodies/ann/facing/cam", "hri/bodies/cat/facing/cam"]
    assert ledger.rejected[Rejection.INTERNAL_ERROR] == 1 and faults.failing
    # one bug met, one error (a defect found: the batch's failure and bob's alone
    # counted it twice)
    assert ledger.decided["worker_errors"] == 1
    frames = [p for p in said if p.kind is Kind.FRAME]
    assert b'"bodies_tracked":["ann","cat"]' in frames[-1].payload  # bob rolled back


class FailsOnAnnAndBobTogether(JsonOutput):
    """A bug only two poses together meet: each alone goes through."""

    def on_changes(self, changes: Changes) -> list[Publication]:
        if {"ann", "bob"} <= {state.body_id for state in changes.results}:
            raise RuntimeError("a bug for ann and bob together")
        return super().on_changes(changes)


def test_a_bug_no_single_pose_meets_is_one_error_and_loses_nothing():
    made, ledger, _, faults = decisions_with(FailsOnAnnAndBobTogether("hri", "test", 100))
    made.flush([sample("ann", sec=1), sample("bob", sec=1)], 0.0)
    assert ledger.decided["worker_errors"] == 1 and faults.failing
    assert ledger.rejected[Rejection.INTERNAL_ERROR] == 0
    assert set(made.tracker.tracked_per_frame()) == {"cam"}


def test_a_turn_without_errors_clears_degraded():
    made, _, outbox, faults = decisions_with(JsonOutput("hri", "test", 100))
    faults.caught(RuntimeError("earlier"), "a test")
    faults.end_turn(True)
    assert faults.failing
    made.flush([sample("ann", sec=1)], 0.0)
    faults.end_turn(True)
    assert not faults.failing and poses_said(outbox, made) == 1


def poses_said(outbox: Outbox, made: Decisions) -> int:
    made.to_outbox()
    return sum(p.kind is Kind.RESULT for p in outbox.take(0))


class FailsOnAsNewClock(JsonOutput):
    """A bug met on the result of a body followed on its tracker's new clock."""

    def on_changes(self, changes: Changes) -> list[Publication]:
        if any(s.body_id == "a" and s.stamp.sec < 100 for s in changes.results):
            raise RuntimeError("a bug on the new clock")
        return super().on_changes(changes)


def test_a_bug_in_a_restart_counts_the_rest_of_the_batch_once():
    """A defect found: the restart's part ran after the batch's first part was counted and
    kept; a bug in it had every pose go again, so ``b`` was counted accepted and then
    refused as out of order. The whole is one transaction now."""
    from facing_service.core.tracker import RESTART_EVIDENCE

    made, ledger, outbox, _ = decisions_with(FailsOnAsNewClock("hri", "test", 100))
    made.flush([sample("a", sec=1000)], 0.0)
    for i in range(RESTART_EVIDENCE - 1):  # the first of the new clock's poses, refused
        made.flush([sample("a", sec=1 + i)], 0.1 * i)
    made.flush([sample("b", sec=5), sample("a", sec=RESTART_EVIDENCE)], 1.0)
    made.to_outbox()
    assert ledger.decided["samples_accepted"] == 2  # a at 1000, b once
    assert ledger.rejected[Rejection.OUT_OF_ORDER] == RESTART_EVIDENCE - 1  # a's, not b's
    assert ledger.rejected[Rejection.INTERNAL_ERROR] == 1  # a on its new clock, alone
    results = [p.key for p in outbox.take(0) if p.kind is Kind.RESULT]
    assert results.count("hri/bodies/b/facing/cam") == 1
