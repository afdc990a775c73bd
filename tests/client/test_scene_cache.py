"""The client's scene events from two lists of a frame's groups (pure)."""

from __future__ import annotations

from facing_service.client.scene import changes
from facing_service.contract.schemas import Centre, GroupState


def group(gid: str, *members: str, robot: bool = False) -> GroupState:
    return GroupState(id=gid, members=list(members), robot=robot, centre=Centre(x=1, y=0))


def test_a_group_the_robot_leaves_is_changed_and_the_robot_left_it():
    before = [group("1", "a", robot=True), group("2", "b", "c")]
    after = [group("1", "a", "d"), group("3", "e", "f", robot=True)]
    assert [(name, args[1].id) for name, args in changes("map", before, after)] == [
        ("group_changed", "1"),
        ("robot_left", "1"),
        ("group_formed", "3"),
        ("robot_joined", "3"),
        ("group_dissolved", "2"),
    ]
    assert changes("map", after, after) == []


def test_groups_dissolved_while_a_seed_is_under_way_stay_dissolved():
    """Before: the frame was forgotten when its groups dissolved, so the seed's older
    answer, applied after, formed them again for good."""
    from facing_service.client.scene import SceneCache
    from facing_service.contract.schemas import FrameGroups

    def said(sec: int, *groups: GroupState) -> FrameGroups:
        return FrameGroups(frame="map", stamp={"sec": sec, "nanosec": 0}, groups=list(groups),
                           people_left_out=0)  # fmt: skip

    cache = SceneCache()
    cache.apply_groups(said(1, group("1", "a", "b")), now=1.0)
    began = 5.0  # a seed is asked; the service answers with the group
    assert [name for name, _ in cache.apply_groups(said(2), now=5.5)] == ["group_dissolved"]
    assert cache.apply_groups(said(1, group("1", "a", "b")), now=6.0, seeded_since=began) == []
    assert cache.groups("map") == []
    formed = cache.apply_groups(said(3, group("2", "a", "c")), now=7.0, seeded_since=6.5)
    assert [name for name, _ in formed] == ["group_formed"]  # a later seed: taken


def test_the_scene_queues_its_events_in_the_order_the_cache_changed():
    """Before: events were queued after the lock was let go, so the seeding thread and the
    inbox could queue "changed" before "formed"."""
    from facing_service.client.scene import SceneListener
    from facing_service.contract.schemas import FrameGroups

    held: list[bool] = []
    listener = SceneListener("hri", "map", lambda _: True, lambda _: held.append(lock.locked()))
    lock = listener._lock
    said = FrameGroups(frame="map", stamp={"sec": 1, "nanosec": 0}, groups=[group("1", "a", "b")],
                       people_left_out=0)  # fmt: skip
    listener._take(said)
    listener.forget("s1")
    assert held == [True, True]
