"""One frame's history, as tf2's TimeCache keeps it: ordered whatever the arrival order,
bounded by time and count, interpolated between its two closest transforms, and refusing
with tf2's own messages what it cannot answer."""

from __future__ import annotations

import math

import pytest

from facing_service.core.tf.cache import MAX_CACHE_ENTRIES, StaticCache, Stored, TimeCache
from facing_service.core.tf.errors import ExtrapolationError
from facing_service.core.tf.geometry import RigidTransform

S = 1_000_000_000


def at(stamp: int, x: float = 0.0, parent: str = "map") -> Stored:
    return Stored(stamp, parent, RigidTransform((x, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)))


def test_out_of_order_inserts_are_kept_newest_first_and_repeats_refused():
    cache = TimeCache(10 * S)
    for stamp in (3 * S, 1 * S, 2 * S):
        assert cache.insert(at(stamp)) is None
    assert [item.stamp for item in cache.items] == [3 * S, 2 * S, 1 * S]
    assert cache.insert(at(2 * S)) == "repeated_data"
    assert cache.stamps(1 * S, 3 * S) == [2 * S, 3 * S]


def test_history_is_bounded_by_time_and_by_count():
    cache = TimeCache(10 * S)
    cache.insert(at(20 * S))
    assert cache.insert(at(5 * S)) == "old_data"  # older than the newest minus 10 s
    cache.insert(at(31 * S))
    assert [item.stamp for item in cache.items] == [31 * S]  # 20 s fell out of the window
    many = TimeCache(10 * S)
    for i in range(MAX_CACHE_ENTRIES + 5):
        many.insert(at(i))
    assert len(many.items) == MAX_CACHE_ENTRIES and many.items[-1].stamp == 5


def test_a_lookup_between_two_transforms_interpolates_and_outside_them_is_refused():
    cache = TimeCache(10 * S)
    cache.insert(at(1 * S, x=0.0))
    cache.insert(at(3 * S, x=2.0))
    assert math.isclose(cache.get(2 * S).transform.translation[0], 1.0)
    assert cache.get(0).stamp == 3 * S  # 0: the latest
    with pytest.raises(ExtrapolationError, match=r"into the future.  Requested time 4.0"):
        cache.get(4 * S)
    with pytest.raises(ExtrapolationError, match="into the past"):
        cache.get(0 * S + 1)


def test_a_static_transform_answers_at_every_time():
    cache = StaticCache()
    assert cache.latest() == (0, None)
    cache.insert(at(5 * S, x=1.0, parent="base_link"))
    assert cache.get(123).stamp == 123 and cache.get(123).transform.translation[0] == 1.0
    assert cache.latest() == (0, "base_link")
