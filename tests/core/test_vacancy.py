"""The place a member just left: kept while clear and by the group, forgotten
once taken, and with the group."""

from __future__ import annotations

import numpy as np

from facing_service.core.social.groups import Group
from facing_service.core.social.vacancy import Vacancies

TRIO = Group(1, frozenset({"a", "b", "c"}), False, (3.0, 0.0))
PAIR = Group(1, frozenset({"a", "b"}), False, (3.0, 0.0))
WHERE = {"a": (3.0, 0.6), "b": (3.0, -0.6), "c": (4.0, 0.0)}


def left_by_c() -> Vacancies:
    v = Vacancies()
    v.seen({1: TRIO}, {}, {TRIO.members}, WHERE)
    v.seen({1: PAIR}, {1: TRIO}, {PAIR.members}, {**WHERE, "c": (9.0, 9.0)})
    return v


NOBODY = np.zeros((0, 2))


def test_the_place_a_member_left_is_kept_while_nobody_takes_it_and_the_group_stays():
    v = left_by_c()
    pair = np.array([WHERE["a"], WHERE["b"]])
    far = np.array([[9.0, 9.0]])
    assert v.place(1, pair, far, clear_m=0.7, body_m=0.3) == (4.0, 0.0)
    assert v.place(1, pair, far, clear_m=0.7, body_m=0.3) == (4.0, 0.0)  # still
    # the members stood beside it (1.17 m, but a member 0.5 m off is no one in it)
    beside = pair + np.array([0.5, 0.0])
    assert left_by_c().place(1, beside, NOBODY, clear_m=0.7, body_m=0.3) == (4.0, 0.0)


def test_a_place_taken_or_left_behind_is_forgotten():
    v = left_by_c()
    pair = np.array([WHERE["a"], WHERE["b"]])
    someone = np.array([[4.1, 0.1]])
    assert v.place(1, pair, someone, clear_m=0.7, body_m=0.3) is None
    assert v.place(1, pair, NOBODY, clear_m=0.7, body_m=0.3) is None  # forgotten, not back
    stepped_in = np.array([WHERE["a"], (3.9, 0.1)])  # b steps into it
    assert left_by_c().place(1, stepped_in, NOBODY, clear_m=0.7, body_m=0.3) is None
    away = pair + np.array([5.0, 0.0])  # the pair walked on: the place is not theirs now
    assert left_by_c().place(1, away, NOBODY, clear_m=0.7, body_m=0.3) is None


def test_a_group_gone_takes_its_places_with_it():
    v = left_by_c()
    v.seen({}, {1: PAIR}, set(), WHERE)
    pair = np.array([WHERE["a"], WHERE["b"]])
    assert v.place(1, pair, NOBODY, clear_m=0.7, body_m=0.3) is None


def test_two_leaving_at_once_leave_the_place_nearest_the_robot_whatever_their_names():
    """A defect found by reading: the largest id was taken as "the last to leave" when several
    left in one update: the place kept depended on what people were called."""
    places = {}
    for near, far in (("x", "y"), ("y", "x")):
        quartet = Group(1, frozenset({"a", "b", near, far}), False, (3.0, 0.0))
        where = {"a": (3.0, 0.6), "b": (3.0, -0.6), near: (2.4, 0.0), far: (3.6, 0.0)}
        v = Vacancies()
        v.seen({1: quartet}, {}, {quartet.members}, where)
        v.seen({1: PAIR}, {1: quartet}, {PAIR.members}, {**where, near: (9, 9), far: (8, 8)})
        pair = np.array([where["a"], where["b"]])
        places[near] = v.place(1, pair, NOBODY, clear_m=0.5, body_m=0.3)
    assert places == {"x": (2.4, 0.0), "y": (2.4, 0.0)}
