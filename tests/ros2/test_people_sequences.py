"""Who is there, as whom, over sequences a ROS4HRI robot really sends: lists that gain and
drop ids (and flicker for one message), links made, moved and dropped, faces under a
camera frame not yet connected, /tf at any moment. The real ``People`` and the real
tracker are driven together, and checked at every step against a reference model that
says the rules as plainly as they can be said."""

from __future__ import annotations

from dataclasses import dataclass, field

from hypothesis import settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, rule

from facing_service.contract.keys import BodyRef
from facing_service.contract.stamps import Time
from facing_service.core.tf.geometry import RigidTransform
from facing_service.ros2.people import People, TfInput, Update

from trackers import tracker

FACES, BODIES, PERSONS = (
    "/humans/faces/tracked",
    "/humans/bodies/tracked",
    "/humans/persons/tracked",
)
LISTS = {"face_": FACES, "body_": BODIES}
S = 1_000_000_000
PERSON_IDS, FACE_IDS, BODY_IDS = ["p1", "p2", "p3"], ["f1", "f2", "f3"], ["b1", "b2", "b3"]
#: Where each frame is (one place each: a pose says which frame it was read from).
PLACE = {f"face_{f}": (1.0 + i, 0.5, 1.6) for i, f in enumerate(FACE_IDS)} | {
    f"body_{b}": (1.0 + i, -0.5, 1.0) for i, b in enumerate(BODY_IDS)
}


def tf(parent: str, child: str, stamp: int, at=(0.0, 0.0, 0.0)) -> TfInput:
    return TfInput(parent, child, Time(stamp), RigidTransform(at, (0.0, 0.0, 0.0, 1.0)))


class Robot:
    """The service's side: People and a tracker, fed as the ROS 2 input feeds them, with
    every refusal the tracker makes kept (none is expected on any sequence)."""

    def __init__(self) -> None:
        self.people = People("base_link")
        self.core = tracker(stale_after_s=1e6)
        self.refused: list[str] = []
        self.now = 0.0

    def feed(self, update: Update) -> None:
        self.now += 0.001
        changes = self.core.ingest(update.poses, self.now)
        self.refused += [f"out_of_order {s.body_id} {s.pose.stamp}" for s in changes.out_of_order]
        self.refused += [f"restart {s.body_id}" for s in changes.restarted]
        if update.lost:
            lost = [BodyRef(frame_id="base_link", body_id=s) for s in update.lost]
            self.core.lose(lost, self.now)
        self.refused += [reason for reason, _ in update.refused]

    def tracked(self) -> dict[str, tuple]:
        """Subject -> (where it looks from, where it stands), as the tracker holds it."""
        return {
            s.body_id: (track.pose.translation, track.pose.stance and track.pose.stance[0])
            for s, track in ((t.state, t) for t in self.core._tracks.values())
        }


@dataclass
class Reference:
    """The rules, as plainly as they can be said (ros2/participants' invariants)."""

    tracked: dict[str, set[str]] = field(
        default_factory=lambda: {FACES: set(), BODIES: set(), PERSONS: set()}
    )
    links: dict[str, dict[str, str]] = field(default_factory=lambda: {"face_": {}, "body_": {}})
    linked_at: dict[tuple[str, str], int] = field(default_factory=dict)  # (kind, person)
    clock: int = 0
    connected: bool = False  # the camera the faces hang under, linked to base_link

    def link(self, person: str, kind: str, target: str) -> None:
        if self.links[kind].get(person, "") == target:
            return
        self.clock += 1
        self.links[kind].pop(person, None)
        if target:
            self.links[kind][person] = target
            self.linked_at[kind, person] = self.clock

    def holder(self, frame: str) -> str | None:
        """The tracked person that linked ``frame`` last, if any."""
        kind, _, ros_id = frame.partition("_")
        claims = [
            (self.linked_at[kind + "_", p], p)
            for p, target in self.links[kind + "_"].items()
            if target == ros_id and p in self.tracked[PERSONS]
        ]
        return "person_" + max(claims)[1] if claims else None

    def participants(self) -> dict[str, tuple[list[str], str | None]]:
        """Subject -> (the frames it may look from, in order; its body when apart)."""
        out = {}
        for person in self.tracked[PERSONS]:
            subject = "person_" + person
            mine = [
                (kind + target, target in self.tracked[LISTS[kind]])
                for kind in ("face_", "body_")
                if (target := self.links[kind].get(person))
                and self.holder(kind + target) == subject
            ]
            looks = [f for f, on in mine if on] or [f for f, _ in mine]
            body = "body_" + self.links["body_"].get(person, "-")
            apart = body in looks[1:] and body[5:] in self.tracked[BODIES]
            out[subject] = (looks, body if apart else None)
        for kind, topic in LISTS.items():
            for ros_id in self.tracked[topic]:
                if self.holder(kind + ros_id) is None:
                    out[kind + ros_id] = ([kind + ros_id], None)
        return out

    def reachable(self, frame: str) -> bool:
        return frame.startswith("body_") or self.connected

    def expected(self) -> dict[str, tuple]:
        """After a /tf of every frame: where each participant looks from and stands."""
        out = {}
        for subject, (looks, body) in self.participants().items():
            frame = next((f for f in looks if self.reachable(f)), None)
            if frame is not None:
                out[subject] = (PLACE[frame], PLACE[body] if body and body != frame else None)
        return out


IDS = {PERSONS: PERSON_IDS, FACES: FACE_IDS, BODIES: BODY_IDS}


class PeopleMachine(RuleBasedStateMachine):
    @initialize(connected=st.booleans())
    def start(self, connected: bool) -> None:
        self.robot, self.reference = Robot(), Reference()
        self.stamp = 0
        self.ticked = False  # a /tf of every frame since the last list or link change
        if connected:
            self.connect()

    def connect(self) -> None:
        update = self.robot.people.on_tf([tf("base_link", "cam", 0)], static=True)
        self.reference.connected = True
        self.robot.feed(update)

    @rule()
    def camera_connected(self) -> None:
        if not self.reference.connected:
            self.connect()
            self.ticked = False

    @rule(topic=st.sampled_from([PERSONS, FACES, BODIES]), data=st.data())
    def list_changes(self, topic: str, data: st.DataObject) -> None:
        ids = data.draw(st.sets(st.sampled_from(IDS[topic])))
        self._list(topic, ids)

    def _list(self, topic: str, ids: set[str]) -> None:
        self.robot.feed(self.robot.people.on_tracked(topic, sorted(ids)))
        self.reference.tracked[topic] = set(ids)
        self.ticked = False

    @rule(topic=st.sampled_from([PERSONS, FACES, BODIES]), data=st.data())
    def an_id_flickers(self, topic: str, data: st.DataObject) -> None:
        """An id drops out of its list for one message and comes back."""
        now = set(self.reference.tracked[topic])
        if now:
            gone = data.draw(st.sampled_from(sorted(now)))
            self._list(topic, now - {gone})
            self._list(topic, now)

    @rule(
        person=st.sampled_from(PERSON_IDS),
        kind=st.sampled_from(["face_id", "body_id"]),
        data=st.data(),
    )
    def link(self, person: str, kind: str, data: st.DataObject) -> None:
        pool = FACE_IDS if kind == "face_id" else BODY_IDS
        target = data.draw(st.sampled_from(["", *pool]))
        self.robot.feed(self.robot.people.on_person_link(person, kind, target))
        self.reference.link(person, kind[:4] + "_", target)
        self.ticked = False

    @rule()
    def tf_of_every_frame(self) -> None:
        self.stamp += S // 30
        faces = [tf("cam", f, self.stamp, PLACE[f]) for f in PLACE if f.startswith("face_")]
        bodies = [tf("base_link", b, self.stamp, PLACE[b]) for b in PLACE if b.startswith("body_")]
        self.robot.feed(self.robot.people.on_tf([*faces, *bodies], static=False))
        self.ticked = True

    @invariant()
    def the_same_participants(self) -> None:
        assert self.robot.people.subjects() == sorted(self.reference.participants())

    @invariant()
    def nobody_tracked_who_is_not_there(self) -> None:
        assert set(self.robot.tracked()) <= set(self.reference.participants())

    @invariant()
    def each_looks_and_stands_where_the_rules_say_after_a_tf(self) -> None:
        if self.ticked:
            assert self.robot.tracked() == self.reference.expected()

    @invariant()
    def nothing_refused(self) -> None:
        assert self.robot.refused == []


PeopleMachine.TestCase.settings = settings(max_examples=200, stateful_step_count=40, deadline=None)
test_people_sequences = PeopleMachine.TestCase


# -- the sequences that broke it, each as a robot sent it --------------------------------


def test_an_anonymous_person_replaced_by_a_known_one_leaves_one_participant():
    """hri_person_manager's usual flow. Before: ['body_b1', 'person_alice'], the
    anonymous person recorded as the body's owner and never released."""
    robot = Robot()
    people = robot.people
    robot.feed(people.on_tf([tf("base_link", "cam", 0)], static=True))
    frames = [tf("cam", "face_f1", S, PLACE["face_f1"]), tf("base_link", "body_b1", S)]
    robot.feed(people.on_tf(frames, static=False))
    robot.feed(people.on_tracked(FACES, ["f1"]))
    robot.feed(people.on_tracked(BODIES, ["b1"]))
    robot.feed(people.on_person_link("anon", "face_id", "f1"))
    robot.feed(people.on_person_link("anon", "body_id", "b1"))
    robot.feed(people.on_tracked(PERSONS, ["anon"]))
    robot.feed(people.on_tracked(FACES, []))  # the face drops out for one message
    frames = [tf("cam", "face_f1", 2 * S, PLACE["face_f1"]), tf("base_link", "body_b1", 2 * S)]
    robot.feed(people.on_tf(frames, static=False))  # the person reads its body meanwhile
    robot.feed(people.on_tracked(FACES, ["f1"]))
    robot.feed(people.on_person_link("alice", "face_id", "f1"))
    robot.feed(people.on_person_link("alice", "body_id", "b1"))
    robot.feed(people.on_tracked(PERSONS, ["anon", "alice"]))
    robot.feed(people.on_tracked(PERSONS, ["alice"]))  # the anonymous one leaves
    frames = [tf("cam", "face_f1", 3 * S, PLACE["face_f1"]), tf("base_link", "body_b1", 3 * S)]
    robot.feed(people.on_tf(frames, static=False))
    assert people.subjects() == ["person_alice"]
    assert sorted(robot.tracked()) == ["person_alice"] and robot.refused == []


def test_a_person_whose_body_left_its_list_stands_where_it_looks_not_where_it_was():
    """Before: the body's last /tf stayed its stance, so a person who walked 3 m away was
    grouped where its lost body had been."""
    robot = Robot()
    people = robot.people
    robot.feed(people.on_tf([tf("base_link", "cam", 0)], static=True))
    frames = [tf("cam", "face_f1", S, (2.0, 0, 1.6)), tf("base_link", "body_b1", S, (2.0, 0, 1))]
    robot.feed(people.on_tf(frames, static=False))
    robot.feed(people.on_person_link("p1", "face_id", "f1"))
    robot.feed(people.on_person_link("p1", "body_id", "b1"))
    for topic, ids in ((FACES, ["f1"]), (BODIES, ["b1"]), (PERSONS, ["p1"])):
        robot.feed(people.on_tracked(topic, ids))
    assert robot.tracked()["person_p1"] == ((2.0, 0, 1.6), (2.0, 0, 1))
    robot.feed(people.on_tracked(BODIES, []))  # the body is lost; its last /tf stays
    robot.feed(people.on_tf([tf("cam", "face_f1", 2 * S, (5.0, 0, 1.6))], static=False))
    assert robot.tracked()["person_p1"] == ((5.0, 0, 1.6), None)


def test_a_person_whose_face_cannot_be_looked_up_looks_from_its_body():
    """Before: nobody at all (the body was the person's, and the person read only its
    face, under a camera frame not yet connected)."""
    robot = Robot()
    people = robot.people
    frames = [tf("cam", "face_f1", S, (2.0, 0, 1.6)), tf("base_link", "body_b1", S, (2.0, 0, 1))]
    robot.feed(people.on_tf(frames, static=False))
    for topic, ids in ((FACES, ["f1"]), (BODIES, ["b1"]), (PERSONS, ["p1"])):
        robot.feed(people.on_tracked(topic, ids))
    robot.feed(people.on_person_link("p1", "face_id", "f1"))
    robot.feed(people.on_person_link("p1", "body_id", "b1"))
    assert robot.tracked() == {"person_p1": ((2.0, 0, 1), None)}
    robot.feed(people.on_tf([tf("base_link", "cam", 0)], static=True))  # connected now
    frames = [tf("cam", "face_f1", 2 * S, (2.0, 0, 1.6)), tf("base_link", "body_b1", 2 * S)]
    robot.feed(people.on_tf(frames, static=False))
    assert robot.tracked()["person_p1"] == ((2.0, 0, 1.6), (0.0, 0.0, 0.0))


def test_faces_and_bodies_a_person_links_a_moment_after_they_appear_are_never_refused():
    """Before: each cost up to 64 out_of_order rejections and a WARNING (the body's first
    results said again when it came back as its own after the person's list flickered)."""
    robot = Robot()
    people = robot.people
    robot.feed(people.on_tracked(BODIES, ["b1"]))
    for k in range(1, 31):  # a second of the body alone
        robot.feed(people.on_tf([tf("base_link", "body_b1", k * S // 30)], static=False))
    robot.feed(people.on_person_link("p1", "body_id", "b1"))
    robot.feed(people.on_tracked(PERSONS, ["p1"]))
    robot.feed(people.on_tracked(PERSONS, []))  # the person's list flickers
    robot.feed(people.on_tracked(PERSONS, ["p1"]))
    for k in range(31, 40):
        robot.feed(people.on_tf([tf("base_link", "body_b1", k * S // 30)], static=False))
    assert robot.refused == [] and sorted(robot.tracked()) == ["person_p1"]
