"""When a robot's clock went back, told from /tf stamps alone (ros2/time_back): in a row,
from one publisher, over a quarter of a second, at most one clear in two seconds."""

from __future__ import annotations

from facing_service.contract.stamps import NS_PER_S as S
from facing_service.ros2.time_back import (
    CLEAR_MIN_INTERVAL_S,
    TIME_BACK_MESSAGES,
    TIME_BACK_NS,
    TIME_BACK_SPAN_S,
    TimeBack,
)

NEWEST = 100 * S
BACK = [(10 * S, NEWEST)]  # a transform 90 s older than its frame's newest
FRESH = [(NEWEST + S // 30, NEWEST)]


def test_messages_in_a_row_from_one_publisher_over_the_span_tell_it():
    told = TimeBack()
    gaps = [i * TIME_BACK_SPAN_S / (TIME_BACK_MESSAGES - 1) for i in range(TIME_BACK_MESSAGES)]
    said = [told.observe(BACK, b"robot", 5.0 + gap) for gap in gaps]
    assert said[:-1] == [0] * (TIME_BACK_MESSAGES - 1) and said[-1] == 90 * S
    assert told.clears == 1 and not told.under_way


def test_a_fresh_message_between_ends_the_run_and_a_burst_tells_nothing():
    told = TimeBack()
    told.observe(BACK, b"robot", 1.0)
    assert told.under_way
    told.observe(FRESH, b"robot", 1.01)  # time goes on: the run starts over
    assert not told.under_way
    burst = [told.observe(BACK, b"robot", 1.02 + i * 0.001) for i in range(10)]
    assert burst == [0] * 10 and told.clears == 0  # ten in 10 ms: not a clock gone back


def test_another_publisher_starts_its_own_run():
    told = TimeBack()
    for i in range(TIME_BACK_MESSAGES - 1):
        told.observe(BACK, b"robot", 1.0 + i * 0.2)
    assert told.observe(BACK, b"stranger", 1.5) == 0  # not the robot's run
    assert told.clears == 0


def test_within_the_interval_a_second_clear_is_refused_and_counted():
    told = TimeBack()
    for t in (1.0, 1.2, 1.4):
        told.observe(BACK, None, t)
    assert told.clears == 1
    for t in (1.6, 1.8, 2.0):
        told.observe(BACK, None, t)
    assert (told.clears, told.clears_refused) == (1, 1)
    later = 1.4 + CLEAR_MIN_INTERVAL_S + 0.1
    for t in (later, later + 0.2, later + 0.4):
        told.observe(BACK, None, t)
    assert told.clears == 2


def test_within_the_margin_is_not_back_and_a_stamp_without_time_is_no_sign():
    told = TimeBack()
    near = [(NEWEST - TIME_BACK_NS + 1, NEWEST)]
    assert [told.observe(near, None, t) for t in (1.0, 1.2, 1.4)] == [0, 0, 0]
    assert told.observe([(None, NEWEST)], None, 1.6) == 0 and not told.under_way
