"""Who is who on a ROS4HRI robot (ros2/participants, issue 75): a tracked person is the
participant, its face where it looks, its body where it stands; a face or body no tracked
person links stands alone; a frame is one person's. People's made scenes are in
test_people.py."""

from __future__ import annotations

from facing_service.ros2.participants import PERSONS, aliases, look_frame, stance_frame

FACES, BODIES = "/humans/faces/tracked", "/humans/bodies/tracked"


def tracked(persons=(), faces=(), bodies=()) -> dict[str, set[str]]:
    return {PERSONS: set(persons), FACES: set(faces), BODIES: set(bodies)}


LINKS = {"face_": {"p1": "f1", "p2": "f2"}, "body_": {"p1": "b1", "p3": "b3"}}


def test_a_person_looks_from_its_face_else_its_body_a_tracked_one_first():
    now = tracked(["p1", "p2", "p3"], faces=["f1"], bodies=["b1", "b3"])
    assert look_frame("p1", now, LINKS) == "face_f1"
    assert look_frame("p3", now, LINKS) == "body_b3"  # no face linked
    assert look_frame("p4", now, LINKS) is None
    turned = tracked(["p1"], faces=[], bodies=["b1"])  # its face lost, its body tracked
    assert look_frame("p1", turned, LINKS) == "body_b1"
    assert look_frame("p2", tracked(["p2"]), LINKS) == "face_f2"  # no list says: as linked


def test_a_person_stands_in_its_body_when_it_looks_from_its_face():
    now = tracked(["p1", "p3"], faces=["f1"], bodies=["b1", "b3"])
    assert stance_frame("p1", now, LINKS) == "body_b1"
    assert stance_frame("p3", now, LINKS) is None  # looks from its body: stands there too
    assert stance_frame("p2", now, LINKS) is None  # no body


def test_the_faces_and_bodies_of_tracked_persons_are_theirs_and_no_one_elses():
    now = tracked(["p1", "p2", "p3"], faces=["f1", "f9"], bodies=["b1"])
    assert aliases(now, LINKS, {}) == {"face_f1": "person_p1", "body_b1": "person_p1"}
    # f2 untracked, b3 untracked, f9 linked by nobody: none is anyone's
    clones = {"face_": {f"c{i}": "f1" for i in range(200)} | {"p1": "f1"}, "body_": {}}
    many = tracked(["p1", *(f"c{i}" for i in range(200))], faces=["f1"])
    assert aliases(many, clones, {"face_f1": "person_p1"}) == {"face_f1": "person_p1"}
    assert aliases(many, clones, {}) == {"face_f1": "person_c0"}  # the first by id
