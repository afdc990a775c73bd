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
