"""Groups and who faces whom through the live service: published on change,
one key per group with a DELETE when it dissolves, answered as queryables; the robot a
participant. Real zenoh sessions on loopback."""

from __future__ import annotations

import math

import pytest

from loopback import get, send, send_delete, wait_until, wait_until_answered
from poses import pose_json

NAMESPACE = "hri"
GROUPS, GAZING = f"{NAMESPACE}/groups/cam", f"{NAMESPACE}/gazing/cam"


def pose_key(body: str) -> str:
    return f"{NAMESPACE}/bodies/{body}/pose/cam"


@pytest.fixture
def scene(net):
    service, ep = net.service(group_hold_s=0.2)
    client = net.client(ep)
    groups = net.recorder(client, f"{NAMESPACE}/groups/**")
    gazing = net.recorder(client, f"{NAMESPACE}/gazing/**")
    wait_until_answered(client, f"{NAMESPACE}/facing/cam")
    return service, client, groups, gazing


def test_two_people_talking_form_a_group_said_on_its_key_and_queryable(scene):
    service, client, groups, gazing = scene
    send(client, pose_key("ann"), pose_json("ann", "cam", x=3.0, y=2.0, yaw_deg=0.0))
    send(client, pose_key("bob"), pose_json("bob", "cam", x=4.2, y=2.0, yaw_deg=180.0))
    said = groups.wait_for(lambda i: i.key == GROUPS and i.value["groups"])[-1].value
    (group,) = said["groups"]
    assert group["members"] == ["ann", "bob"] and group["robot"] is False
    assert group["centre"]["x"] == pytest.approx(3.6, abs=0.05)
    assert said["frame"] == "cam" and said["instance"] == service.settings.instance
    (one,) = groups.wait_for(lambda i: i.key == f"{GROUPS}/{group['id']}" and i.kind == "put")
    assert one.value == group
    pairs = gazing.wait_for(lambda i: i.key == GAZING and len(i.value["pairs"]) == 2)[-1]
    assert {(p["sender"], p["receiver"], p["mutual"]) for p in pairs.value["pairs"]} == {
        ("ann", "bob", True),
        ("bob", "ann", True),
    }
    assert dict(get(client, GROUPS))[GROUPS] == said
    assert dict(get(client, f"{NAMESPACE}/gazing/*"))[GAZING] == pairs.value

    # bob walks away: the group dissolves, its key is DELETEd, the list empties
    send_delete(client, pose_key("bob"))
    groups.wait_for(lambda i: i.key == f"{GROUPS}/{group['id']}" and i.kind == "delete")
    groups.wait_for(lambda i: i.key == GROUPS and i.value["groups"] == [])
    assert service.status().counters["scene_published"] >= 4


def test_a_person_facing_the_robot_is_in_a_group_with_it(scene):
    _, client, groups, gazing = scene
    send(client, pose_key("cat"), pose_json("cat", "cam", x=1.0, y=0.0))  # faces the robot
    said = groups.wait_for(lambda i: i.key == GROUPS and i.value["groups"])[-1].value
    assert said["groups"][0]["robot"] is True and said["groups"][0]["members"] == ["cat"]
    pairs = gazing.wait_for(lambda i: i.key == GAZING and i.value["pairs"])[-1].value["pairs"]
    assert {(p["sender"], p["receiver"]) for p in pairs} == {("cat", ""), ("", "cat")}


def test_a_threshold_on_groups_is_refused_by_name(scene):
    service, client, _, _ = scene
    (reply,) = get(client, f"{GROUPS}?threshold_deg=30")
    assert reply[0] == "error"
    assert "threshold_deg applies to facing results" in reply[1]["detail"]
    assert service.status().counters["queries_refused"] == 1


def test_a_crowd_is_cut_and_counted(net):
    service, ep = net.service(group_max_people=3)
    client = net.client(ep)
    groups = net.recorder(client, f"{NAMESPACE}/groups/**")
    wait_until_answered(client, f"{NAMESPACE}/facing/cam")
    for i in range(6):
        send(client, pose_key(f"p{i}"), pose_json(f"p{i}", "cam", x=2.0 + i, yaw_deg=90.0))
    groups.wait_for(lambda i: i.key == GROUPS and i.value["people_left_out"] == 3)
    assert service.status().counters["scene_people_left_out"] >= 3


def test_the_client_says_groups_formed_changed_dissolved_and_the_robot_joining_and_leaving(net):
    """FacingClient's callbacks, in order, as a behaviour would use them; its cache
    seeded by a query for a group formed before it started."""
    import queue

    from facing_service import FacingClient

    from loopback import loopback_config

    _service, ep = net.service(group_hold_s=0.1)
    tracker = net.client(ep)
    wait_until_answered(tracker, f"{NAMESPACE}/facing/cam")
    send(tracker, pose_key("ann"), pose_json("ann", "cam", x=3.0, y=2.0, yaw_deg=0.0))
    send(tracker, pose_key("bob"), pose_json("bob", "cam", x=4.2, y=2.0, yaw_deg=180.0))
    wait_until(lambda: any(r[1]["groups"] for r in get(tracker, GROUPS)), 5, "a group")
    events: queue.SimpleQueue = queue.SimpleQueue()
    with FacingClient(session_config=loopback_config(connect=[ep])) as hri:
        (seeded,) = hri.groups("cam")
        assert seeded.members == ["ann", "bob"] and not seeded.robot
        assert {(p.sender, p.receiver) for p in hri.gazing("cam")} == {
            ("ann", "bob"),
            ("bob", "ann"),
        }
        registrations = {
            "group_formed": hri.on_group_formed,
            "group_changed": hri.on_group_changed,
            "group_dissolved": hri.on_group_dissolved,
            "robot_joined": hri.on_robot_joined,
            "robot_left": hri.on_robot_left,
        }
        for name, register in registrations.items():
            register(lambda frame, group, *_, name=name: events.put((name, frame, group)))
        # cat steps up facing the robot: a second group, with the robot
        send(tracker, pose_key("cat"), pose_json("cat", "cam", x=1.0, y=-1.0, sec=2))
        assert [events.get(timeout=5)[0] for _ in range(2)] == ["group_formed", "robot_joined"]
        send_delete(tracker, pose_key("cat"))
        got = [events.get(timeout=5) for _ in range(2)]
        assert [(n, g.robot) for n, _, g in got] == [
            ("group_dissolved", True),
            ("robot_left", True),
        ]
        send_delete(tracker, pose_key("bob"))
        name, frame, group = events.get(timeout=5)
        assert (name, frame, group.id) == ("group_dissolved", "cam", seeded.id)


@pytest.mark.parametrize("base_frame", ["*", "cam"])
def test_a_query_naming_a_frame_always_answers_even_after_the_room_emptied(net, base_frame):
    """A defect found: after everyone left and people came back, a query on the frame's groups
    got no reply at all. A frame the service knows answers with its empty lists; a frame
    it does not know answers with an error naming the frames tracked; a wildcard that
    matches nothing stays unanswered (every queryable would refuse it)."""
    _, ep = net.service(group_hold_s=0.2, base_frame=base_frame)
    client = net.client(ep)
    wait_until_answered(client, f"{NAMESPACE}/services/facing/*/status")
    for sec in (1, 2):  # the room fills, and empties: twice
        ann = pose_json("ann", "cam", x=3.0, y=2.0, yaw_deg=0.0, sec=sec)
        send(client, pose_key("ann"), ann)
        send(client, pose_key("bob"), pose_json("bob", "cam", x=4.2, y=2.0, yaw_deg=180.0, sec=sec))
        wait_until(lambda: dict(get(client, GROUPS)).get(GROUPS, {}).get("groups"), 5, "a group")
        send_delete(client, pose_key("ann"))
        send_delete(client, pose_key("bob"))
        wait_until(lambda: not get(client, f"{NAMESPACE}/bodies/*/facing/*"), 5, "everyone gone")
        # the group dissolves once held: till then the query says it, then says it is gone
        wait_until(lambda: [(k, v["groups"]) for k, v in get(client, GROUPS)] == [(GROUPS, [])],
                   5, "the empty groups answered")  # fmt: skip
        assert [(k, v["pairs"]) for k, v in get(client, GAZING)] == [(GAZING, [])]
        ((key, facing),) = get(client, f"{NAMESPACE}/facing/cam")
        assert key == f"{NAMESPACE}/facing/cam" and facing["bodies_tracked"] == []
        ((kind, error),) = get(client, f"{NAMESPACE}/bodies/*/facing/cam")
        assert (kind, error["error"]) == ("error", "empty_frame")
    # A wrong frame is answered as such, with one --base-frame too (it stayed
    # silent, and a typo looked like an empty room)
    ((kind, error),) = get(client, f"{NAMESPACE}/groups/cma")
    assert (kind, error["error"]) == ("error", "unknown_frame") and "'cma'" in error["detail"]
    assert get(client, f"{NAMESPACE}/bodies/*/facing/*") == []  # a wildcard: nothing to refuse


def test_where_to_stand_goes_out_with_the_groups(scene):
    """Where to stand, on the wire: a pair talking ahead carries where the robot should join them;
    a person engaging from 2.4 m away, in no group, where to greet them; both queryable."""
    _, client, groups, _ = scene
    send(client, pose_key("ann"), pose_json("ann", "cam", x=3.0, y=0.6, yaw_deg=-90.0))
    send(client, pose_key("bob"), pose_json("bob", "cam", x=3.0, y=-0.6, yaw_deg=90.0))
    said = groups.wait_for(lambda i: i.key == GROUPS and i.value["groups"])[-1].value
    (group,) = said["groups"]
    join = group["join"]
    assert join["x"] < 3.0 and abs(join["y"]) < 0.3 and abs(join["yaw"]) < 0.2
    send(client, pose_key("cy"), pose_json("cy", "cam", x=-2.4, y=0.0, yaw_deg=0.0))  # faces us
    wait_until(
        lambda: [g["body_id"] for g in dict(get(client, GROUPS))[GROUPS]["greetings"]] == ["cy"],
        5.0,
        "cy greeted",
    )
    (greeting,) = dict(get(client, GROUPS))[GROUPS]["greetings"]
    assert greeting["place"]["x"] == pytest.approx(-1.2, abs=0.05)
    assert abs(greeting["place"]["yaw"]) == pytest.approx(math.pi, abs=0.05)  # facing cy (-x)
