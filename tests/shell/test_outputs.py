"""The output forms on their own: what our JSON keys say for a tracker call, with and
without anyone listening to results, and the robot's topics' start line."""

from __future__ import annotations

from facing_service.config.settings import Settings
from facing_service.contract.keys import BodyRef
from facing_service.core.snapshot import TurnSnapshot
from facing_service.shell.compose import robot_for
from facing_service.shell.outbox import Kind
from facing_service.shell.outputs import JsonOutput, RosTopicsOutput

from trackers import sample, tracker


def changes():
    t = tracker()
    first = t.ingest([sample("a", sec=1)], 0.0)
    return first, t.lose([BodyRef(frame_id="cam", body_id="a")], 0.0)


def test_json_keys_say_results_while_heard_and_state_changes_always():
    output = JsonOutput("hri", "front", 100)
    first, lost = changes()
    said = output.on_changes(first)
    assert [p.kind for p in said][:1] == [Kind.RESULT] and said[0].key == "hri/bodies/a/facing/cam"
    assert b'"instance":"front"' in said[0].payload
    output._heard.matching(False)  # what the sender's matching listener says with nobody
    unheard = output.on_changes(first)
    assert Kind.RESULT not in {p.kind for p in unheard}
    assert [p.kind for p in unheard] == [p.kind for p in said if p.kind is not Kind.RESULT]
    said_lost = {(p.kind, p.payload is None) for p in output.on_changes(lost)}
    assert said_lost >= {(Kind.RESULT, True), (Kind.ENGAGEMENT, True), (Kind.FRAME, False)}


def test_a_subscriber_appearing_wakes_the_worker_to_say_every_current_result():
    output = JsonOutput("hri", "test", 100)
    woken: list[bool] = []
    output.wake_with(lambda: woken.append(True))
    t = tracker()
    t.ingest([sample("a", sec=1), sample("b", sec=1)], 0.0)
    heard = output._heard
    heard.matching(False)  # nobody: nothing due, nothing woken
    assert output.next_due() is None and woken == []
    heard.matching(True)  # a subscriber appeared
    assert woken == [True] and output.next_due() == 0.0
    said = output.tick(0.0, TurnSnapshot(t))
    assert [p.key for p in said] == ["hri/bodies/a/facing/cam", "hri/bodies/b/facing/cam"]
    assert output.next_due() is None and output.tick(0.0, TurnSnapshot(t)) == []
    heard.matching(True)  # still there: nothing new to say
    assert woken == [True]


def test_the_re_say_leaves_out_results_said_since_the_subscriber_appeared():
    """zenoh's routing knows a new subscriber before its matching listener tells the
    service: a pose handled in between has its result sent (it reached the subscriber),
    and the re-say that follows must not send it again (CI saw the duplicate)."""
    output = JsonOutput("hri", "test", 100)
    t = tracker()
    heard = output._heard
    heard.matching(False)
    unheard = t.ingest([sample("a", sec=1), sample("b", sec=1)], 0.0)
    assert Kind.RESULT not in {p.kind for p in output.on_changes(unheard)}
    heard.matching(True)  # a subscriber appeared
    said = output.on_changes(t.ingest([sample("a", sec=2)], 0.0))
    assert [p.key for p in said if p.kind is Kind.RESULT] == ["hri/bodies/a/facing/cam"]
    re_said = output.tick(0.0, TurnSnapshot(t))
    assert [p.key for p in re_said] == ["hri/bodies/b/facing/cam"]  # b's was never heard
    heard.matching(False)
    heard.matching(True)  # another appearance: a's result is due again this time
    assert len(output.tick(0.0, TurnSnapshot(t))) == 2


def test_a_subscriber_gone_and_another_come_before_the_re_say_misses_nothing():
    """A defect found: the bodies said after the first appearance were left out of the re-say
    for a second subscriber that came after the first had gone: it never heard them."""
    output = JsonOutput("hri", "test", 100)
    t = tracker()
    heard = output._heard
    heard.matching(False)
    output.on_changes(t.ingest([sample("a", sec=1), sample("b", sec=1)], 0.0))
    heard.matching(True)  # the first subscriber
    output.on_changes(t.ingest([sample("a", sec=2)], 0.0))  # a's heard by the first
    heard.matching(False)  # it leaves, and another comes, before the worker's turn
    heard.matching(True)
    re_said = output.tick(0.0, TurnSnapshot(t))
    assert sorted(p.key for p in re_said) == ["hri/bodies/a/facing/cam", "hri/bodies/b/facing/cam"]


def test_an_appearance_between_the_workers_check_and_its_clear_is_kept():
    """A defect found: ``if joined: ... joined = False`` on the worker's thread could clear a
    join zenoh's thread set in between. Taking the due appearance is one step now: one
    made after it is due at the next turn."""
    output = JsonOutput("hri", "test", 100)
    t = tracker()
    t.ingest([sample("a", sec=1)], 0.0)
    heard = output._heard
    heard.matching(False)
    heard.matching(True)
    assert len(output.tick(0.0, TurnSnapshot(t))) == 1  # the first appearance's re-say
    heard.matching(False)
    heard.matching(True)  # right after the take: due again, not lost
    assert output.next_due() == 0.0 and len(output.tick(0.0, TurnSnapshot(t))) == 1


def test_json_keys_have_no_periodic_work_and_the_robots_topics_say_what_they_add():
    settings = Settings(output="ros2", ros_intents=True)
    json_output = JsonOutput("hri", "test", 100)
    assert json_output.next_due() is None and json_output.start_line() == ""
    ros = RosTopicsOutput(robot_for(settings, answering=True), 1.0, True, "facing_service")
    assert ros.start_line().endswith("markers, /intents)")
    assert ros.next_due() is not None  # engagement_status is republished every period
