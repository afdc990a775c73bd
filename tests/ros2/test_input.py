"""ROS 2 input: a robot's /tf, /tf_static and /humans/* topics, in rmw_zenoh's and the
bridge's formats, through a zenoh router into the real service."""

from __future__ import annotations

import json
import logging
import math
import time

import pytest

from facing_service.contract.poses import Rejected, Rejection
from facing_service.contract.stamps import Time
from facing_service.core.detector import classify_one
from facing_service.core.tf_math import RigidTransform
from facing_service.ros2 import types as ros2_types
from facing_service.ros2.input import RosSample, route
from facing_service.ros2.people import MAX_FRAME_NAME, People, TfInput
from facing_service.ros2.wire import (
    FORM_EVIDENCE,
    HASH_NOT_SUPPORTED,
    Attachment,
    Distro,
    FormLearner,
    RosFormat,
    Wire,
    attachment,
    attachment_layout,
)

import rmw_zenoh
from loopback import endpoint
from oracles import oracle
from rmw_zenoh import Release, Robot
from ros_messages import S, ids_list, string, tf_message, transform, type_of, yaw_q

TF_HASH = "RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087"


# -- keys and attachments ---------------------------------------------------------------


def test_keys_in_both_formats():
    assert (
        Wire().key("/tf", ros2_types.TF_MESSAGE)
        == f"0/tf/tf2_msgs::msg::dds_::TFMessage_/{TF_HASH}"
    )
    wire = Wire(RosFormat.RMW_ZENOH, 7, "bot1")
    key = wire.key("/humans/faces/tracked", ros2_types.IDS_LIST)
    assert key.startswith("7/bot1/humans/faces/tracked/hri_msgs::msg::dds_::IdsList_/RIHS01_")
    assert wire.topic_of(key) == "/humans/faces/tracked"
    assert wire.topic_of("8/bot1/tf/x/y") is None and wire.topic_of("7/bot2/tf/x/y") is None
    bridge = Wire(RosFormat.BRIDGE, namespace="bot1")
    assert bridge.key("/tf", ros2_types.TF_MESSAGE) == "bot1/tf"
    assert bridge.topic_of("bot1/humans/persons/p1/face_id") == "/humans/persons/p1/face_id"
    assert Wire(RosFormat.BRIDGE).key("/tf_static", ros2_types.TF_MESSAGE) == "tf_static"


def test_the_type_hash_is_checked_per_sample():
    wire = Wire()
    good = wire.key("/tf", ros2_types.TF_MESSAGE)
    assert wire.check(good, ros2_types.TF_MESSAGE) is None
    humble = good.rsplit("/", 1)[0] + "/" + HASH_NOT_SUPPORTED
    assert wire.check(humble, ros2_types.TF_MESSAGE) is None  # Humble sends no hash
    wrong = good.rsplit("/", 1)[0] + "/RIHS01_" + "0" * 64
    assert "type hash" in wire.check(wrong, ros2_types.TF_MESSAGE)
    other = wire.key("/tf", ros2_types.STRING)
    assert "is not tf2_msgs/msg/TFMessage" in wire.check(other, ros2_types.TF_MESSAGE)


def test_humble_keys_carry_no_type_hash():
    humble = Wire(distro=Distro.HUMBLE)
    assert humble.key("/tf", ros2_types.TF_MESSAGE) == (
        "0/tf/tf2_msgs::msg::dds_::TFMessage_/TypeHashNotSupported"
    )


@pytest.mark.parametrize("release", [rmw_zenoh.HUMBLE_0_1_1, rmw_zenoh.JAZZY_0_2_10], ids=str)
def test_attachments_in_both_layouts_parse_as_rmw_zenoh_parses_them(release):
    """Ours, read back by the parser written from that release's attachment_helpers.cpp
    (and zenoh-ros2-sdk's, for the current layout)."""
    layout = Attachment.KEYED if release.keyed_attachment else Attachment.CURRENT
    gid = bytes(range(16))
    data = attachment(7, 1_700_000_000_123_456_789, gid, layout)
    assert rmw_zenoh.parse_attachment(release, data) == (7, gid)
    assert attachment_layout(data) is layout
    assert attachment_layout(rmw_zenoh.make_attachment(release, 1, gid)) is layout
    assert attachment_layout(data[:-1]) is None and attachment_layout(None) is None


def test_the_robots_form_is_learned_from_its_keys_and_attachments():
    humble_key = Wire(distro=Distro.HUMBLE).key("/tf", ros2_types.TF_MESSAGE)
    keyed = rmw_zenoh.make_attachment(rmw_zenoh.HUMBLE_0_1_1, 1, bytes(16))
    learner = FormLearner()
    assert learner.current.distro is Distro.JAZZY  # until the robot says otherwise
    level, line = learner.learn(humble_key, attachment_layout(keyed), 0.0)
    assert level == logging.INFO
    assert "Humble" in line and "keyed" in line and humble_key in line
    assert (learner.current.distro, learner.current.attachment) == (
        Distro.HUMBLE,
        Attachment.KEYED,
    )
    assert learner.learn(humble_key, attachment_layout(keyed), 0.1) is None  # said once
    assert learner.learn("tf", None, 0.2) is None  # the bridge's: nothing to learn
    forced = FormLearner(Distro.JAZZY)
    level, line = forced.learn(humble_key, attachment_layout(keyed), 0.0)
    assert level == logging.WARNING
    assert "--ros-distro jazzy" in line and forced.current.distro is Distro.JAZZY


def test_another_form_needs_sustained_evidence_and_two_robots_are_each_answered():
    """A form flip used to follow any one sample. Now the first form is taken at once,
    another needs FORM_EVIDENCE samples (a few strays change nothing), and once two are
    heard the service answers in both; one silent for FORM_FORGET_S is dropped."""
    jazzy = Wire().key("/tf", ros2_types.TF_MESSAGE)
    humble = Wire(distro=Distro.HUMBLE).key("/tf", ros2_types.TF_MESSAGE)
    current = rmw_zenoh.make_attachment(rmw_zenoh.JAZZY_0_2_10, 1, bytes(16))
    learner = FormLearner()
    assert learner.learn(jazzy, attachment_layout(current), 0.0) is not None
    for i in range(FORM_EVIDENCE - 1):  # strays: not enough to answer in their form
        assert learner.learn(humble, attachment_layout(current), 0.01 * i) is None
    assert [f.distro for f in learner.forms] == [Distro.JAZZY] and learner.changes == 0
    level, line = learner.learn(
        humble, attachment_layout(current), 0.5
    )  # sustained: a second robot
    assert level == logging.INFO and "each of" in line
    assert [f.distro for f in learner.forms] == [Distro.JAZZY, Distro.HUMBLE]
    assert learner.changes == 1
    for t in (1.0, 5.0, 10.4):  # the Humble robot goes on, the Jazzy one is silent
        learner.learn(humble, attachment_layout(current), t)
    assert [f.distro for f in learner.forms] == [Distro.HUMBLE] and learner.changes == 2
    assert (
        learner.learn(jazzy, attachment_layout(current), 10.5) is None
    )  # back, but must show it again
    assert [f.distro for f in learner.forms] == [Distro.HUMBLE]


def test_a_service_that_does_not_answer_says_what_the_robot_does_not_that_it_answers():
    """--output json: the form is still learned (and shown), but nothing is answered."""
    key = Wire(distro=Distro.HUMBLE).key("/tf", ros2_types.TF_MESSAGE)
    extra = rmw_zenoh.make_attachment(rmw_zenoh.HUMBLE_0_1_9, 1, bytes(16))
    _, line = FormLearner(answering=False).learn(key, attachment_layout(extra), 0.0)
    assert line.startswith("the robot publishes in rmw_zenoh's form for Humble")
    assert "answering" not in line


# -- people, without a network -------------------------------------------------------------


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
    assert people.on_person_link("p1", "face_id", "f1").poses == []  # same stamp: not newer
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


# -- every ROS 2 rejection reason -----------------------------------------------------------


def _route(people: People, key: str, payload: bytes) -> object:
    return route(people, Wire(), RosSample(key, payload))


TF_KEY = Wire().key("/tf", ros2_types.TF_MESSAGE)


@pytest.mark.parametrize(
    ("key", "payload", "reason"),
    [
        (TF_KEY.rsplit("/", 1)[0] + "/RIHS01_" + "f" * 64, tf_message(), Rejection.TYPE_MISMATCH),
        (TF_KEY, tf_message(transform("a", "b", S))[:-7], Rejection.MALFORMED_CDR),
        (TF_KEY, b"", Rejection.MALFORMED_CDR),
        ("0/chatter/std_msgs::msg::dds_::String_/x", string("hi"), Rejection.INVALID_KEY),
    ],
    ids=["wrong-hash", "truncated-cdr", "empty", "unknown-topic"],
)
def test_bad_samples_are_refused_with_a_reason(key, payload, reason):
    result = _route(People("base_link"), key, payload)
    assert isinstance(result, Rejected) and result.reason is reason


@pytest.mark.parametrize(
    ("transforms", "reason"),
    [
        ([transform("base_link", "x", S, (math.nan, 0.0, 0.0))], "tf_nan"),
        ([transform("base_link", "x", S, q=(0.0, 0.0, 0.0, 1.5))], "tf_denormalized_quaternion"),
        ([transform("x", "x", S)], "tf_self_transform"),
        ([transform("", "x", S)], "tf_no_frame_id"),
        ([transform("base_link", "", S)], "tf_no_child_frame_id"),
        ([transform("base_link", "x", 20 * S), transform("base_link", "x", S)], "tf_old_data"),
        ([transform("base_link", "x", S), transform("base_link", "x", S)], "tf_repeated_data"),
    ],
)
def test_tf2s_input_checks_are_counted_rejections(transforms, reason):
    update = _route(People("base_link"), TF_KEY, tf_message(*transforms))
    assert [r for r, _ in update.refused] == [reason]
    assert Rejection(reason)  # a stable code the status counts


def test_ids_outside_our_alphabet_are_refused():
    key = Wire().key("/humans/bodies/tracked", ros2_types.IDS_LIST)
    update = _route(People("base_link"), key, ids_list(["ok", "no/slash"]))
    assert [r for r, _ in update.refused] == ["invalid_id"]


# -- end to end, through a router -----------------------------------------------------------


@pytest.fixture
def robot_site(net):
    """A router (the robot's), and a function starting the service and a robot on it."""
    router = net.router()
    ep = endpoint(router.port)
    made: list[Robot] = []

    def start(fmt: RosFormat = RosFormat.RMW_ZENOH, **settings):
        return net.robot_service(ep, base_frame="base_link", ros_format=fmt.value, **settings)

    def robot(release: Release = rmw_zenoh.JAZZY_0_2_10, **where) -> Robot:
        """A robot written from rmw_zenoh's (or the bridge's) sources, not from ours."""
        r = Robot(net.client(ep, mode="client", timestamping=release.bridge), release, **where)
        made.append(r)
        return r

    yield start, robot, net.client(ep, mode="client")
    for r in made:
        r.close()


def say(robot: Robot, topic: str, cdr: bytes, *, latched: bool = False) -> None:
    """One message of the robot's on ``topic`` (``latched``: transient-local)."""
    robot.publish(topic, type_of(topic), cdr, latched=latched)


def wait_for(predicate, timeout: float = 10.0):
    deadline = time.monotonic() + timeout
    while not (value := predicate()):
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.02)
    return value


def results_of(recorder, body: str) -> list[dict]:
    return [i.value for i in recorder.items if i.kind == "put" and i.value["body_id"] == body]


@pytest.mark.parametrize(
    "release", [rmw_zenoh.JAZZY_0_2_10, rmw_zenoh.HUMBLE_0_1_9, rmw_zenoh.BRIDGE_1_10_0], ids=str
)
def test_a_robots_body_gives_exact_results_in_every_form(net, robot_site, release):
    start, make_robot, consumer = robot_site
    fmt = RosFormat.BRIDGE if release.bridge else RosFormat.RMW_ZENOH
    service = start(fmt, ros_namespace="bot1", ros_domain_id=3)
    robot = make_robot(release, namespace="bot1", domain=3)
    results = net.recorder(consumer, "hri/bodies/*/facing/base_link")
    time.sleep(0.5)  # the robot's session learns the service's subscriptions
    # base_link -> camera (static) -> body_a, the person 2 m ahead of the robot, 10 deg off.
    say(
        robot,
        "/tf_static",
        tf_message(transform("base_link", "camera", 0, (0.1, 0.0, 1.2))),
        latched=True,
    )
    say(robot, "/humans/bodies/tracked", ids_list(["a"]))
    body = transform("camera", "body_a", 5 * S, (1.9, 0.0, -1.2), yaw_q(190.0))
    say(robot, "/tf", tf_message(body))
    (state,) = wait_for(lambda: results_of(results, "body_a"))
    expected = classify_one((2.0, 0.0, 0.0), yaw_q(190.0), 20.0)
    assert state["facing"] is True and state["angle_deg"] == pytest.approx(expected[1], abs=1e-9)
    assert state["distance_m"] == pytest.approx(2.0, abs=1e-12)
    assert state["stamp"] == {"sec": 5, "nanosec": 0}
    # The body leaves the tracked list: lost at once.
    say(robot, "/humans/bodies/tracked", ids_list([]))
    results.wait_for(lambda i: i.kind == "delete" and i.key == "hri/bodies/body_a/facing/base_link")
    assert service.status().rejected["type_mismatch"] == 0


def test_bad_samples_are_counted_and_never_lose_a_good_one(net, robot_site):
    start, make_robot, consumer = robot_site
    service = start()
    robot = make_robot()
    results = net.recorder(consumer, "hri/bodies/*/facing/base_link")
    time.sleep(0.5)
    say(robot, "/humans/bodies/tracked", ids_list(["a"]))
    wrong_hash = Wire().key("/tf", ros2_types.TF_MESSAGE).rsplit("/", 1)[0] + "/RIHS01_" + "0" * 64
    good = tf_message(transform("base_link", "body_a", 2 * S, (2.0, 0.0, 0.0), yaw_q(180.0)))
    stray = tf_message(transform("base_link", "body_a", S, (1.0, 0, 0)))
    robot.session.put(
        wrong_hash, stray, attachment=rmw_zenoh.make_attachment(robot.release, 1, bytes(16))
    )
    say(robot, "/tf", good[:-5])  # truncated CDR
    say(robot, "/tf", tf_message(transform("base_link", "body_a", S, (math.nan, 0.0, 0.0))))
    say(robot, "/tf", good)
    (state,) = wait_for(lambda: results_of(results, "body_a"))
    assert state["stamp"]["sec"] == 2 and state["facing"]
    rejected = service.status().rejected
    assert (rejected["type_mismatch"], rejected["malformed_cdr"], rejected["tf_nan"]) == (1, 1, 1)


def test_tf_static_published_before_the_service_starts_is_used(net, robot_site):
    """Transient-local: the robot's /tf_static is in its publisher's cache before the
    service exists; the service's advanced subscriber fetches it."""
    start, make_robot, consumer = robot_site
    robot = make_robot()
    say(
        robot,
        "/tf_static",
        tf_message(transform("base_link", "camera", 0, (0.5, 0.0, 1.0))),
        latched=True,
    )
    time.sleep(0.3)
    start()
    results = net.recorder(consumer, "hri/bodies/*/facing/base_link")
    # Without /tf_static, camera is not connected to base_link and no result can exist;
    # the body streams at 30 Hz meanwhile, as a tracker does.
    for i in range(300):
        body = transform("camera", "body_a", 3 * S + i * (S // 30), (1.5, 0.0, -1.0), yaw_q(180))
        say(robot, "/humans/bodies/tracked", ids_list(["a"]))  # volatile: streamed
        say(robot, "/tf", tf_message(body))
        if results_of(results, "body_a"):
            break
        time.sleep(1 / 30)
    state = wait_for(lambda: results_of(results, "body_a"))[0]
    assert state["distance_m"] == pytest.approx(2.0) and state["facing"]


def test_a_body_three_links_from_base_link_is_what_tf2_computes(net, robot_site):
    """base_link -> torso (static) -> head_camera (dynamic, moving) -> body_a (dynamic):
    the service's result equals tf2's own lookup (ROS's BufferCore) fed the same data."""
    start, make_robot, consumer = robot_site
    service = start()
    robot = make_robot()
    results = net.recorder(consumer, "hri/bodies/*/facing/base_link")
    time.sleep(0.5)
    q_pan = (0.0, 0.0, math.sin(0.2), math.cos(0.2))
    ops = [
        ["set", "base_link", "torso", 0, [0.0, 0.0, 0.8], [0.0, 0.0, 0.0, 1.0], True],
        ["set", "torso", "head_camera", 1 * S, [0.1, 0.0, 0.5], [0, 0, 0, 1], False],
        ["set", "torso", "head_camera", 3 * S, [0.1, 0.0, 0.5], list(q_pan), False],
        ["set", "head_camera", "body_a", 2 * S, [2.0, 0.3, -1.1], list(yaw_q(170)), False],
        ["lookup", "base_link", "body_a", 0],
    ]
    say(
        robot,
        "/tf_static",
        tf_message(transform("base_link", "torso", 0, (0.0, 0.0, 0.8))),
        latched=True,
    )
    say(robot, "/humans/bodies/tracked", ids_list(["a"]))
    for op in ops[1:4]:
        _, parent, child, stamp, t, q, _ = op
        say(robot, "/tf", tf_message(transform(parent, child, stamp, tuple(t), tuple(q))))
    ((want,),) = oracle([ops])
    stamp = want["stamp"]
    state = wait_for(
        lambda: [s for s in results_of(results, "body_a") if s["stamp"]["sec"] == stamp // S]
    )[-1]
    r, angle, _, facing = classify_one(tuple(want["t"]), tuple(want["q"]), 20.0)
    assert state["robot_in_body"] == pytest.approx({"x": r[0], "y": r[1], "z": r[2]}, abs=1e-9)
    assert state["angle_deg"] == pytest.approx(angle, abs=1e-9) and state["facing"] is facing
    assert service.status().rejected["tf_old_data"] == 0


def test_persons_engage_through_their_face(net, robot_site):
    start, make_robot, consumer = robot_site
    start()
    robot = make_robot()
    events = net.recorder(consumer, "hri/events/engagement/base_link")
    time.sleep(0.5)
    say(robot, "/humans/persons/tracked", ids_list(["p1"]), latched=True)
    say(robot, "/humans/persons/p1/face_id", string("f1"), latched=True)
    say(robot, "/humans/faces/tracked", ids_list(["f1"]))
    # The face 1.2 m ahead at head height, looking straight at the robot's origin.
    pitch = math.atan2(1.5, 1.2)  # looking down at base_link's origin
    q = (0.0, math.sin(pitch / 2), 0.0, math.cos(pitch / 2))
    for i in range(90):
        stamp = S + i * (S // 30)
        face = transform("base_link", "face_f1", stamp, (1.2, 0.0, 1.5), _face_toward_origin(q))
        say(robot, "/tf", tf_message(face))
        time.sleep(0.005)
    (event,) = events.wait_for(
        lambda i: i.value["body_id"] == "person_p1" and i.value["level"] == "ENGAGED"
    )
    # ENGAGING at once, ENGAGED once ENGAGING held 1 s with the face in the cone
    # (--head-dwell-s; issue 52's defaults: sustained attention off, the soft vote on)
    assert json.loads(event.payload)["stamp"]["sec"] == 2


def _face_toward_origin(pitch_q):
    """Yaw 180 deg (face the robot) then pitch down: q = yaw * pitch."""
    yx, yy, yz, yw = yaw_q(180.0)
    px, py, pz, pw = pitch_q
    return (
        yw * px + yx * pw + yy * pz - yz * py,
        yw * py - yx * pz + yy * pw + yz * px,
        yw * pz + yx * py - yy * px + yz * pw,
        yw * pw - yx * px - yy * py - yz * pz,
    )


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


@pytest.mark.parametrize(
    ("sec", "nanosec", "t", "reason"),
    [
        (2**31 - 1, 2**32 - 1, (1.0, 0.0, 0.0), "tf_invalid_stamp"),  # uninitialised
        (-5, 0, (1.0, 0.0, 0.0), "tf_invalid_stamp"),
        (1, 0, (1.7e308, 0.0, 0.0), "tf_out_of_range"),
        (1, 0, (0.0, -1e10, 0.0), "tf_out_of_range"),
    ],
    ids=["uninitialised-stamp", "negative-seconds", "huge", "beyond-the-json-bound"],
)
def test_numbers_no_output_can_carry_are_refused_at_intake(sec, nanosec, t, reason):
    """One out-of-range stamp used to become a frame's newest and make every later batch
    raise (Stamp.sec <= 2**31-1); 1.7e308 m published inf. Both are refused, counted."""
    message = ros2_types.message_type(ros2_types.TF_MESSAGE)(
        transforms=[transform("base_link", "body_a", 0, t)]
    )
    message.transforms[0].header.stamp.sec = sec
    message.transforms[0].header.stamp.nanosec = nanosec
    people = People("base_link")
    people.on_tracked("/humans/bodies/tracked", ["a"])
    update = _route(people, TF_KEY, ros2_types.serialize(message, ros2_types.TF_MESSAGE))
    assert [r for r, _ in update.refused] == [reason] and update.poses == []
    assert Rejection(reason)
    assert not people.tf.has_frame("body_a")  # never entered the buffer


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


def test_cloned_person_ids_pointing_at_a_real_face_make_no_results():
    """200 fresh person ids whose face_id names a real person's face used to multiply that
    face's results 200-fold (each with its first results). A frame is the pose of one
    person at a time: the clones are refused as link_taken, once each."""
    people = People("base_link")
    people.on_tracked("/humans/faces/tracked", ["f1"])
    people.on_tf([tf_in("base_link", "face_f1", 1, (1.0, 0, 0))], static=False)
    people.on_person_link("real", "face_id", "f1")
    people.on_tracked("/humans/persons/tracked", ["real"])
    clones = [f"c{i}" for i in range(200)]
    refused = []
    for clone in clones:
        refused += people.on_person_link(clone, "face_id", "f1").refused
    update = people.on_tracked("/humans/persons/tracked", ["real", *clones])
    refused += update.refused
    assert update.poses == []
    assert [r for r, _ in refused] == ["link_taken"] * 200
    poses = people.on_tf([tf_in("base_link", "face_f1", 2, (1.0, 0, 0))], static=False).poses
    assert sorted(p.body_id for p in poses) == ["face_f1", "person_real"]
    # the real person leaves: the face is free for the next person who resolves it
    people.on_tracked("/humans/persons/tracked", clones)
    poses = people.on_tf([tf_in("base_link", "face_f1", 3, (1.0, 0, 0))], static=False).poses
    assert {p.body_id for p in poses if p.body_id.startswith("person_")} == {"person_c0"}
