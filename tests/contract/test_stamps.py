"""Time in one shape: integer nanoseconds, with the sec/nanosec views the wire carries."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from facing_service.contract.stamps import MAX_NANOSEC, MAX_SEC, NS_PER_S, ZERO, Stamp, Time

secs = st.integers(0, MAX_SEC)
nanosecs = st.integers(0, MAX_NANOSEC)


@given(secs, nanosecs)
def test_the_views_and_the_wire_form_round_trip(sec, nanosec):
    t = Time.of(sec, nanosec)
    assert (t.sec, t.nanosec) == (sec, nanosec) and t == sec * NS_PER_S + nanosec
    assert Time.from_model(t.model()) == t and t.model() == Stamp(sec=sec, nanosec=nanosec)
    assert abs(t.seconds - (sec + nanosec / 1e9)) < 1e-6


def test_only_what_builtin_interfaces_time_may_say_is_a_stamp():
    assert Time.checked(MAX_SEC, MAX_NANOSEC) == Time.of(MAX_SEC, MAX_NANOSEC)
    assert Time.checked(-1, 0) is None  # negative seconds
    assert Time.checked(1, NS_PER_S) is None  # an uninitialised stamp's nanoseconds
    assert Time.checked(MAX_SEC + 1, 0) is None  # past the int32


def test_stamps_are_numbers():
    a, b = Time.of(1, 500_000_000), Time.from_seconds(2.0)
    assert ZERO < a < b and b - a == NS_PER_S // 2 and sorted([b, a]) == [a, b]
    assert repr(a) == "Time.of(1, 500000000)"
    # a defect found: a log line said the repr; a person reads seconds (a number format: the ns)
    assert str(a) == f"{a}" == "1.500000000 s" and f"{a:d}" == "1500000000"
