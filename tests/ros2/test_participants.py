"""Who is who on a ROS4HRI robot (ros2/participants): a tracked person is the
participant, its face where it looks, its tracked body where it stands; a face or body
no tracked person holds stands alone; a frame is one person's, the one that linked it
last. People's made scenes are in test_people.py, their sequences in
test_people_sequences.py."""

from __future__ import annotations

from facing_service.ros2.participants import PERSONS, Participant, derive

FACES, BODIES = "/humans/faces/tracked", "/humans/bodies/tracked"


def tracked(persons=(), faces=(), bodies=()) -> dict[str, set[str]]:
    return {PERSONS: set(persons), FACES: set(faces), BODIES: set(bodies)}


LINKS = {"face_": {"p1": "f1", "p2": "f2"}, "body_": {"p1": "b1", "p3": "b3"}}


def looks(now, links=LINKS) -> dict[str, tuple[str, ...]]:
    return {s: p.looks for s, p in derive(now, links).participants.items()}


def test_a_person_looks_from_its_face_else_its_body_a_tracked_one_first():
    now = looks(tracked(["p1", "p2", "p3", "p4"], faces=["f1"], bodies=["b1", "b3"]))
    assert now["person_p1"] == ("face_f1", "body_b1")
    assert now["person_p3"] == ("body_b3",)  # no face linked
    assert now["person_p4"] == ()  # links nothing: no pose
    turned = looks(tracked(["p1"], faces=[], bodies=["b1"]))  # its face lost, body tracked
    assert turned["person_p1"] == ("body_b1",)
    assert looks(tracked(["p2"]))["person_p2"] == ("face_f2",)  # no list says: as linked


def test_a_person_stands_in_its_body_only_while_the_body_is_tracked():
    now = derive(tracked(["p1", "p3"], faces=["f1"], bodies=["b1", "b3"]), LINKS).participants
    assert now["person_p1"] == Participant(("face_f1", "body_b1"), "body_b1")
    assert now["person_p3"].stands is None  # looks from its body: stands there too
    lost_body = derive(tracked(["p1"], faces=["f1"]), LINKS).participants
    assert lost_body["person_p1"] == Participant(("face_f1",), None)  # not where it was


def test_the_faces_and_bodies_of_tracked_persons_are_theirs_and_no_one_elses():
    now = derive(tracked(["p1", "p2", "p3"], faces=["f1", "f9"], bodies=["b1"]), LINKS)
    assert sorted(now.participants) == ["face_f9", "person_p1", "person_p2", "person_p3"]
    assert now.holder["face_f1"] == now.holder["body_b1"] == "person_p1"
    clones = {"face_": {"p1": "f1"} | {f"c{i}": "f1" for i in range(200)}, "body_": {}}
    many = derive(tracked(["p1", *(f"c{i}" for i in range(200))], faces=["f1"]), clones)
    holding = [s for s, p in many.participants.items() if p.looks]
    assert holding == ["person_c199"]  # the last link made, whatever the names
