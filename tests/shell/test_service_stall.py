"""The service off the robot, over a link that stalls and is cut: a stall is
not everyone leaving, and the service says what it hears. The service and a consumer in
processes of their own, the robot through a userspace TCP proxy (stalled_link.py)."""

from __future__ import annotations

import pytest

from stalled_link import play

pytestmark = pytest.mark.slow


def test_a_stall_and_a_cut_lose_nobody_a_departure_and_a_dead_tracker_still_do():
    """Before: a 4 s stall said all three lost (and back from the backlog a moment
    later); a cut (connections reset, refused 2 s) lost both ENGAGED people, who came back
    through ENGAGING; nothing was logged."""
    report = play(stall_s=4.0, hold_s=6.0)
    said = "\n".join(report.log)
    assert report.lost_in_stall == [] and report.drops_in_stall == [], report
    assert report.lost_in_cut == [] and report.drops_in_cut == [], report
    # a person who really leaves while the others go on: lost as before (at 2 s); the
    # dead tracker's people are cleared once the hold is over, and each is said
    assert report.left_lost_after_s > 0 and report.dead_cleared_after_s > 0, report
    assert said.count("the input is silent: nothing heard for 1.0 s") == 3, said
    assert said.count("the input is back after") == 2, said
    assert said.count("people not heard for 6 s (--hold-silent-s) are lost") == 1, said
    assert "Traceback" not in said and report.service_alive
