"""The client's body cache, without a network: which facts become which events."""

from __future__ import annotations

from facing_service.client.bodies import BodyCache
from facing_service.contract.keys import BodyRef
from facing_service.contract.schemas import EngagementEvent, FacingState

ANN = BodyRef(frame_id="cam", body_id="ann")


def state(sec: int, facing: bool, instance: str | None = "s1") -> FacingState:
    return FacingState.model_validate(
        {
            "body_id": "ann", "frame_id": "cam", "facing": facing, "angle_deg": 0.0,
            "distance_m": 1.0, "threshold_deg": 20.0, "stamp": {"sec": sec, "nanosec": 0},
            "instance": instance, "robot_in_body": {"x": 1.0, "y": 0.0, "z": 0.0},
            "position": {"x": 1.0, "y": 0.0, "z": 0.0}, "heading_deg": 180.0,
        }
    )  # fmt: skip


def level(sec: int, name: str, previous: str = "UNKNOWN", instance: str = "s1"):
    values = {"UNKNOWN": 0, "DISENGAGED": 1, "ENGAGING": 2, "ENGAGED": 3, "DISENGAGING": 4}
    return EngagementEvent.model_validate(
        {
            "body_id": "ann", "frame_id": "cam", "level": name, "level_value": values[name],
            "previous": previous, "stamp": {"sec": sec, "nanosec": 0}, "instance": instance,
            "score": 1.0, "zone": "personal",
        }
    )  # fmt: skip


def names(events) -> list[str]:
    return [name for name, _ in events]


def test_transitions_only_and_the_newest_stamp_wins():
    cache = BodyCache()
    cache.live.add("s1")
    assert names(cache.apply(state(1, False))) == ["change"]
    assert names(cache.apply(state(2, True))) == ["change", "facing"]
    assert names(cache.apply(state(3, True))) == ["change"]
    assert cache.apply(state(2, False)) == []  # older than what is held: a raced seed
    assert names(cache.apply(state(4, False))) == ["change", "not_facing"]
    assert names(cache.delete(ANN, 1.0)) == ["lost"]
    assert cache.delete(ANN, 2.0) == []  # unknown: nothing to lose


def test_what_a_dead_instance_says_is_refused_and_counted():
    cache = BodyCache()
    assert cache.apply(state(1, True, instance="gone")) == []
    assert cache.take_level(level(1, "ENGAGED", instance="gone")) == []
    assert cache.dropped_from_dead == 2 and cache.states == {}


def test_disengaged_follows_only_engaged_and_a_vanished_service_loses_its_bodies():
    cache = BodyCache()
    cache.live.add("s1")
    assert cache.take_level(level(1, "DISENGAGED")) == []  # never engaged: nothing to undo
    assert names(cache.take_level(level(2, "ENGAGED", "ENGAGING"))) == ["engaged"]
    cache.apply(state(2, True))
    events = cache.instance_gone("s1")
    assert names(events) == ["disengaged", "lost"]
    gone = events[0][1][0]
    assert (gone.previous, gone.level) == ("ENGAGED", "UNKNOWN")
    assert events[1][1] == (ANN,) and cache.states == {} and cache.levels == {}


def test_a_body_vouched_for_by_two_services_stays_while_one_lives():
    cache = BodyCache()
    cache.live |= {"s1", "s2"}
    cache.apply(state(1, True, instance="s1"))
    cache.apply(state(2, True, instance="s2"))
    assert cache.instance_gone("s1") == []
    assert names(cache.instance_gone("s2")) == ["lost"]
