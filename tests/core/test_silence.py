"""A silent input is held and said, not read as everyone leaving (core.silence, issue 76)."""

from __future__ import annotations

from facing_service.contract.keys import BodyRef
from facing_service.core.silence import Change, InputSilence, SilenceParams

from trackers import sample, tracker

PARAMS = SilenceParams(after_s=1.0, hold_s=10.0)


def test_nothing_heard_for_a_while_with_people_tracked_is_a_silence_that_holds():
    silence = InputSilence(PARAMS)
    assert silence.next_due(tracking=True) is None  # nothing heard yet: nothing to hold
    assert silence.heard(100.0) is None
    assert silence.next_due(tracking=False) is None  # nobody tracked: no silence to say
    assert silence.next_due(tracking=True) == 101.0
    assert silence.look(100.9, tracking=True) is None
    assert silence.look(101.0, tracking=True) is Change.SILENT and silence.holding
    assert silence.look(105.0, tracking=True) is None  # said once
    assert silence.next_due(tracking=True) == 110.0  # the bound
    assert silence.heard(104.0) == 4.0 and not silence.holding  # back: 4 s held
    assert (silence.silences, silence.longest_s) == (1, 4.0)


def test_a_silence_past_its_bound_is_the_input_gone():
    silence = InputSilence(PARAMS)
    silence.heard(100.0)
    assert silence.look(101.5, tracking=True) is Change.SILENT
    assert silence.look(110.0, tracking=True) is Change.GONE and not silence.holding
    assert silence.longest_s == 10.0
    assert silence.heard(130.0) is None  # nothing held any more: nothing to resume


def test_a_hold_of_zero_holds_nothing():
    silence = InputSilence(SilenceParams(after_s=1.0, hold_s=0.0))
    silence.heard(100.0)
    assert silence.next_due(tracking=True) is None
    assert silence.look(105.0, tracking=True) is None and not silence.holding


def test_the_tracker_resumes_where_it_stopped_and_a_body_that_stopped_before_still_goes():
    """Resumed after 4 s held: a body heard just before the silence has its whole
    staleness left; one that had stopped before the silence (its others went on) still
    goes stale at its own time, shifted by the silence alone."""
    t = tracker()  # stale after 2 s
    t.ingest([sample("left", sec=1)], 0.0)  # stops here: it left
    t.ingest([sample("stays", sec=1)], 1.5)  # then the link stalls, from 1.5 s to 5.5 s
    t.resume(4.0)
    assert t.next_expiry() == 0.0 + 4.0 + 2.0  # "left": 0.5 s of input time remained
    assert [b.body_id for b in t.expire(6.0).lost] == ["left"]
    assert t.expire(7.4).lost == [] and t.poses("cam")  # "stays" until 1.5 + 4 + 2 = 7.5
    assert t.expire(7.5).lost == [BodyRef(frame_id="cam", body_id="stays")]
