"""People from the TF tree and the tracked lists: who exists, through which frame, at the
latest common time; what is refused, and what is bounded (ros2/people)."""

from __future__ import annotations

from facing_service.contract.stamps import Time
from facing_service.core.tf.geometry import RigidTransform
from facing_service.ros2.people import MAX_FRAME_NAME, People, TfInput

from ros_messages import S, yaw_q


def tf_in(parent, child, sec, t=(0.0, 0.0, 0.0), q=(0.0, 0.0, 0.0, 1.0)) -> TfInput:
    return TfInput(parent, child, Time(int(sec * S)), RigidTransform(t, q))


def test_the_tracked_lists_define_who_exists():
    people = People("base_link")
    people.on_tf([tf_in("base_link", "body_a", 1, (2.0, 0.0, 0.0), yaw_q(180))], static=False)
    assert people.on_tf([], static=False).poses == []
    (pose,) = people.on_tracked("/humans/bodies/tracked", ["a"]).poses  # known at once
    assert pose.body_id == "body_a" and pose.profile == "body"
    assert pose.pose.translation == (2.0, 0.0, 0.0)
    update = people.on_tracked("/humans/bodies/tracked", [])
    assert update.lost == ["body_a"] and update.poses == []
    assert people.on_tf([tf_in("base_link", "body_a", 2)], static=False).poses == []


def test_a_person_is_seen_through_its_face_else_its_body():
    people = People("base_link")
    people.on_tf(
        [
            tf_in("base_link", "body_b1", 1, (3.0, 0.0, 0.0)),
            tf_in("base_link", "face_f1", 1, (2.0, 0.0, 1.6)),
        ],
        static=False,
    )
    people.on_tracked("/humans/persons/tracked", ["p1"])
    (body,) = people.on_person_link("p1", "body_id", "b1").poses
    assert body.body_id == "person_p1" and body.profile == "body"
    # the face, at the same stamp: where it looks from now (the tracker takes an equal stamp)
    (face,) = people.on_person_link("p1", "face_id", "f1").poses
    assert face.body_id == "person_p1" and face.profile == "head"
    assert face.pose.translation == (2.0, 0.0, 1.6) and face.pose.stance is None  # (b1 untracked)
    (face,) = people.on_tf([tf_in("base_link", "face_f1", 2, (2.0, 0.0, 1.6))], static=False).poses
    assert face.body_id == "person_p1" and face.profile == "head"


def test_poses_move_only_forward_at_the_latest_common_time():
    people = People("base_link")
    people.on_tracked("/humans/bodies/tracked", ["a"])
    update = people.on_tf([tf_in("base_link", "cam", 1), tf_in("cam", "body_a", 1)], static=False)
    assert [p.pose.stamp for p in update.poses] == [Time.of(1)]
    # body_a moves on, but cam has nothing newer: the latest common time stays at 1 s.
    assert people.on_tf([tf_in("cam", "body_a", 2)], static=False).poses == []
    assert people.on_tf([tf_in("cam", "body_a", 3)], static=False).poses == []
    (moved,) = people.on_tf([tf_in("base_link", "cam", 3)], static=False).poses
    assert moved.pose.stamp == Time.of(3)


def test_a_moving_camera_updates_every_body_below_it_and_only_those():
    people = People("base_link")
    people.on_tracked("/humans/bodies/tracked", ["a", "b", "c"])
    people.on_tf(
        [
            tf_in("base_link", "cam", 1),
            tf_in("cam", "body_a", 1),
            tf_in("cam", "body_b", 1),
            tf_in("base_link", "body_c", 1),
        ],
        static=False,
    )
    update = people.on_tf(
        [tf_in("base_link", "cam", 2), tf_in("cam", "body_a", 2), tf_in("cam", "body_b", 2)],
        static=False,
    )
    assert sorted(p.body_id for p in update.poses) == ["body_a", "body_b"]


def test_a_static_transform_into_a_dynamic_frame_is_refused_with_why():
    """The shared two-person recordings give camera_color_optical_frame a /tf parent and
    a /tf_static one; when /tf comes first the static one is refused, as tf2 does: the
    rejection says why, so the log's summary does not alarm a newcomer for nothing."""
    people = People("camera_link")
    people.on_tf([tf_in("camera_link", "optical", 20)], static=False)
    update = people.on_tf([tf_in("camera_color_frame", "optical", 0)], static=True)
    ((reason, what),) = update.refused
    assert reason == "tf_old_data"
    assert what.startswith("camera_color_frame -> optical (a /tf_static transform of a frame")
    assert "harmless when the /tf parent is the one meant" in what


# -- bounds: what a robot can make People hold ----------------------------------------------


def test_a_list_longer_than_max_ids_keeps_the_tracked_first_and_is_counted():
    people = People("base_link", max_ids=3)
    people.on_tracked("/humans/bodies/tracked", ["c"])
    update = people.on_tracked("/humans/bodies/tracked", ["a", "b", "c", "d", "e"])
    assert people.subjects() == ["body_a", "body_b", "body_c"]  # c kept, then list order
    assert update.refused == [("capacity", "/humans/bodies/tracked: 5 ids, only the first 3 kept")]


def test_links_of_untracked_persons_are_kept_then_the_oldest_forgotten():
    """A link may come before its person's list (kept for then); a robot naming persons
    without end costs at most max_ids links of each kind."""
    people = People("base_link", max_ids=2)
    people.on_tf([tf_in("base_link", "body_b1", 1, (2.0, 0.0, 0.0))], static=False)
    assert people.on_person_link("p1", "body_id", "b1").refused == []
    people.on_person_link("p2", "body_id", "b2")
    update = people.on_person_link("p3", "body_id", "b3")
    assert update.refused == [("capacity", "p1/body_id: forgotten, over 2 person links")]
    people.on_tracked("/humans/persons/tracked", ["p2", "p3"])
    assert [people.frame_of(s) for s in people.subjects()] == ["body_b2", "body_b3"]


def test_a_huge_name_is_refused_and_quoted_cut():
    """Frame names are sender-chosen and tf2 keeps every one: a name over MAX_FRAME_NAME
    is refused with its own reason (it is not kept), and quoted cut."""
    people = People("base_link")
    update = people.on_tf([tf_in("base_link", "x" * 1_000_000, 1, (1.0, 0, 0))], static=False)
    ((reason, what),) = update.refused
    assert reason == "tf_frame_name_too_long"
    assert len(what) < 200 and what.endswith("(1000000 chars)")
    assert not people.tf.has_frame("x" * 1_000_000)
    longest = "y" * MAX_FRAME_NAME
    assert people.on_tf([tf_in("base_link", longest, 1, (1.0, 0, 0))], static=False).refused == []


def test_first_results_are_said_from_what_the_buffer_holds():
    """A list handled after the /tf that came with it: the poses of the last 2 s first."""
    people = People("base_link")
    for i in range(90):  # 3 s at 30 Hz before the list
        people.on_tf([tf_in("base_link", "body_a", 1 + i / 30, (2.0, 0.0, 0.0))], static=False)
    poses = people.on_tracked("/humans/bodies/tracked", ["a"]).poses
    stamps = [p.pose.stamp for p in poses]
    assert stamps == sorted(stamps) and len(stamps) == 60  # 2 s at 30 Hz, the latest last
    assert stamps[-1] == int((1 + 89 / 30) * S)


def test_cloned_person_ids_pointing_at_a_real_face_make_one_stream_of_results():
    """200 fresh person ids whose face_id names a real person's face used to multiply that
    face's results 200-fold (each with its first results). A frame is the pose of one
    person at a time, the one that linked it last: the clones take turns at it, and each
    /tf of the face is one result, never 200."""
    people = People("base_link")
    people.on_tracked("/humans/faces/tracked", ["f1"])
    people.on_tf([tf_in("base_link", "face_f1", 1, (1.0, 0, 0))], static=False)
    people.on_person_link("real", "face_id", "f1")
    people.on_tracked("/humans/persons/tracked", ["real"])
    clones = [f"c{i}" for i in range(200)]
    for clone in clones:
        people.on_person_link(clone, "face_id", "f1")
    update = people.on_tracked("/humans/persons/tracked", ["real", *clones])
    assert [p.body_id for p in update.poses] == ["person_c199"] and update.refused == []
    poses = people.on_tf([tf_in("base_link", "face_f1", 2, (1.0, 0, 0))], static=False).poses
    assert [p.body_id for p in poses] == ["person_c199"]
    assert people.subjects() == sorted(f"person_{p}" for p in ["real", *clones])
    # the clones leave: the face is the real person's again, its results resumed
    update = people.on_tracked("/humans/persons/tracked", ["real"])
    assert update.lost == ["person_c199"]
    poses = people.on_tf([tf_in("base_link", "face_f1", 3, (1.0, 0, 0))], static=False).poses
    assert [p.body_id for p in poses] == ["person_real"]


# -- one human, one participant ------------------------------------------------


def _person_with_face_and_body(people: People, sec: float = 1) -> list:
    """p1 links face f1 (at 2 m, looking at the robot) and body b1 (at 2.2 m, turned 90
    degrees: it faces y); all three tracked."""
    poses = []
    poses += people.on_tf(
        [
            tf_in("base_link", "face_f1", sec, (2.0, 0.0, 1.6), yaw_q(180)),
            tf_in("base_link", "body_b1", sec, (2.2, 0.0, 1.0), yaw_q(90)),
        ],
        static=False,
    ).poses
    for topic, ids in (("faces", ["f1"]), ("bodies", ["b1"])):
        poses += people.on_tracked(f"/humans/{topic}/tracked", ids).poses
    poses += people.on_person_link("p1", "face_id", "f1").poses
    poses += people.on_person_link("p1", "body_id", "b1").poses
    poses += people.on_tracked("/humans/persons/tracked", ["p1"]).poses
    return poses


def test_a_person_with_a_face_and_a_body_is_one_participant_looking_and_standing():
    """The person is the participant; its face says where it looks (its pose), its body
    how it stands (the stance, for groups); the face and the body, once the person links
    them, are no subjects of their own: lost as such, never said again."""
    people = People("base_link")
    update_poses = _person_with_face_and_body(people)
    assert people.subjects() == ["person_p1"]
    update = people.on_tf(
        [
            tf_in("base_link", "face_f1", 2, (2.0, 0.0, 1.6), yaw_q(180)),
            tf_in("base_link", "body_b1", 2, (2.2, 0.0, 1.0), yaw_q(90)),
        ],
        static=False,
    )
    (pose,) = update.poses
    assert pose.body_id == "person_p1" and pose.profile == "head"
    assert pose.pose.translation == (2.0, 0.0, 1.6)  # where it looks from: the face
    assert pose.pose.stance is not None and pose.pose.stance[0] == (2.2, 0.0, 1.0)  # the body
    said = {p.body_id for p in update_poses}
    assert said <= {"face_f1", "body_b1", "person_p1"}  # before the links: anonymous


def test_a_face_and_a_body_become_a_persons_and_are_lost_as_their_own():
    people = People("base_link")
    people.on_tf([tf_in("base_link", "face_f1", 1, (2.0, 0.0, 1.6), yaw_q(180))], static=False)
    (alone,) = people.on_tracked("/humans/faces/tracked", ["f1"]).poses
    assert alone.body_id == "face_f1"  # no person links it: a participant of its own
    people.on_person_link("p1", "face_id", "f1")
    update = people.on_tracked("/humans/persons/tracked", ["p1"])
    assert update.lost == ["face_f1"] and [p.body_id for p in update.poses] == ["person_p1"]
    # the person leaves (the face stays): the face is its own participant again, its
    # results resumed after the last said of it (never said twice: the tracker would
    # refuse them as out of order)
    update = people.on_tracked("/humans/persons/tracked", [])
    assert update.lost == ["person_p1"] and update.poses == []
    assert people.subjects() == ["face_f1"]
    (again,) = people.on_tf([tf_in("base_link", "face_f1", 2, (2.0, 0, 1.6))], static=False).poses
    assert again.body_id == "face_f1" and again.pose.stamp == Time.of(2)


def test_two_people_with_faces_only_are_two_participants():
    people = People("base_link")
    people.on_tf(
        [
            tf_in("base_link", "face_a", 1, (2.0, 0.5, 1.6), yaw_q(180)),
            tf_in("base_link", "face_b", 1, (2.0, -0.5, 1.6), yaw_q(180)),
        ],
        static=False,
    )
    poses = people.on_tracked("/humans/faces/tracked", ["a", "b"]).poses
    assert sorted(p.body_id for p in poses) == ["face_a", "face_b"]
    assert people.subjects() == ["face_a", "face_b"]
    assert all(p.pose.stance is None for p in poses)


def test_a_person_linking_a_face_another_holds_takes_it_over_without_a_refusal():
    """A person manager moves a face from an anonymous person to a recognised one: the
    newest link wins at once (before, the second was refused as link_taken, a WARNING
    on the normal flow, until the first left)."""
    people = People("base_link")
    people.on_tf([tf_in("base_link", "face_f1", 1, (2.0, 0.0, 1.6), yaw_q(180))], static=False)
    people.on_tracked("/humans/faces/tracked", ["f1"])
    people.on_person_link("first", "face_id", "f1")
    people.on_tracked("/humans/persons/tracked", ["first"])
    refused = people.on_person_link("second", "face_id", "f1").refused
    update = people.on_tracked("/humans/persons/tracked", ["first", "second"])
    assert refused + update.refused == []
    assert [p.body_id for p in update.poses] == ["person_second"]
    assert "face_f1" not in people.subjects()  # a person's, not a participant of its own
    poses = people.on_tf([tf_in("base_link", "face_f1", 2, (2.0, 0.0, 1.6))], static=False).poses
    assert [p.body_id for p in poses] == ["person_second"]


def test_a_person_whose_face_is_lost_is_seen_through_its_body():
    """Turned away, the face is no longer tracked: the person, still tracked, reads its
    body (it was lost with its face's frame before, at --stale-after-s)."""
    people = People("base_link")
    _person_with_face_and_body(people)
    people.on_tracked("/humans/faces/tracked", [])
    assert people.frame_of("person_p1") == "body_b1"
    poses = people.on_tf([tf_in("base_link", "body_b1", 2, (2.2, 0.0, 1.0))], static=False).poses
    assert [(p.body_id, p.profile, p.pose.stance) for p in poses] == [("person_p1", "body", None)]


def test_a_persons_face_found_again_under_a_new_id_keeps_its_engagement():
    """A face lost and found again under a new id (the person manager relinks
    the person to it) must not reset what was built up about the person: ENGAGED carries
    over, and the new face never becomes a second participant once linked."""
    from facing_service.contract.keys import BodyRef
    from facing_service.contract.levels import Level

    from trackers import tracker

    people, core = People("base_link"), tracker()
    clock = [0.0]

    def feed(update) -> None:
        core.ingest(update.poses, clock[0])
        lost = [BodyRef(frame_id="base_link", body_id=s) for s in update.lost]
        if lost:
            core.lose(lost, clock[0])

    def stream(face: str, seconds: float, start: float) -> None:
        for i in range(int(seconds * 30)):
            clock[0] = start + i / 30
            looking = tf_in("base_link", face, clock[0], (1.5, 0.0, 1.6), yaw_q(180))
            feed(people.on_tf([looking], static=False))

    feed(people.on_tracked("/humans/faces/tracked", ["f1"]))
    feed(people.on_person_link("p1", "face_id", "f1"))
    feed(people.on_tracked("/humans/persons/tracked", ["p1"]))
    stream("face_f1", 8.0, 1.0)
    levels = {e.body_id: e.level for e in core.engagements()}
    assert levels == {"person_p1": Level.ENGAGED}
    # the face is lost; found again as f2, anonymous for a moment, then the person's
    feed(people.on_tracked("/humans/faces/tracked", ["f2"]))
    stream("face_f2", 0.3, 9.0)
    feed(people.on_person_link("p1", "face_id", "f2"))
    stream("face_f2", 1.0, 9.3)
    levels = {e.body_id: e.level for e in core.engagements()}
    assert levels == {"person_p1": Level.ENGAGED}  # f2 a participant no more


# -- a new face or body waits for a person manager to claim it ----------------------------

WAIT = S // 4  # the service's default, --ros-join-wait-s 0.25


def _stream_face(people: People, start_s: float, seconds: float) -> list:
    """face_f1 at 30 Hz from ``start_s``: every update's poses."""
    poses = []
    for i in range(round(seconds * 30)):
        at = start_s + i / 30
        poses += people.on_tf(
            [tf_in("base_link", "face_f1", at, (2.0, 0.0, 1.6))], static=False
        ).poses
    return poses


def test_a_face_claimed_within_the_wait_is_never_a_participant_of_its_own():
    """A face tracker lists the face, its person manager links it 0.1 s later (through
    another subscription): before, face_f1 was emitted, then lost when the person took it
    (a double at every arrival); with the wait, only the person, from the face's first pose."""
    for wait, doubled in ((0, True), (WAIT, False)):
        people = People("base_link", join_wait_ns=wait)
        people.on_tracked("/humans/faces/tracked", ["f1"])
        early = _stream_face(people, 1.0, 0.1)
        people.on_person_link("anon_f1", "face_id", "f1")
        update = people.on_tracked("/humans/persons/tracked", ["anon_f1"])
        later = _stream_face(people, 1.1, 0.5)
        assert ("face_f1" in update.lost) is doubled
        assert {p.body_id for p in early} == ({"face_f1"} if doubled else set())
        person = [p for p in update.poses + later if p.body_id == "person_anon_f1"]
        if not doubled:  # nothing lost: from the face's first pose
            assert person[0].pose.stamp == Time.of(1)
        assert [p.pose.stamp for p in person] == sorted({p.pose.stamp for p in person})


def test_a_face_nobody_claims_waits_then_is_emitted_from_its_first_pose():
    people = People("base_link", join_wait_ns=WAIT)
    people.on_tracked("/humans/faces/tracked", ["f1"])
    updates = [
        people.on_tf([tf_in("base_link", "face_f1", 1 + i / 30, (2.0, 0.0, 1.6))], static=False)
        for i in range(30)
    ]
    # nothing until its own stamps span the wait (the 9th pose, 0.27 s after the first),
    # then every pose since the first: none lost
    first = next(i for i, update in enumerate(updates) if update.poses)
    assert first == 8
    stamps = [p.pose.stamp for update in updates for p in update.poses]
    assert stamps == [Time(int((1 + i / 30) * S)) for i in range(30)]


def test_a_person_is_never_kept_waiting():
    people = People("base_link", join_wait_ns=WAIT)
    people.on_tf([tf_in("base_link", "face_f1", 1, (2.0, 0.0, 1.6))], static=False)
    people.on_tracked("/humans/faces/tracked", ["f1"])
    people.on_person_link("ada", "face_id", "f1")
    (pose,) = people.on_tracked("/humans/persons/tracked", ["ada"]).poses
    assert pose.body_id == "person_ada" and pose.pose.stamp == Time.of(1)
