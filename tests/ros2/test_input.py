"""ROS 2 input: a robot's /tf, /tf_static and /humans/* topics, in rmw_zenoh's and the
bridge's formats, through a zenoh router into the real service."""

from __future__ import annotations

import json
import math
import time

import pytest

from facing_service.contract.poses import Rejected, Rejection
from facing_service.core.detector import classify_one
from facing_service.ros2 import types as ros2_types
from facing_service.ros2.input import RosSample, route
from facing_service.ros2.people import People
from facing_service.ros2.wire import (
    RosFormat,
    Wire,
)

import rmw_zenoh
from loopback import endpoint
from oracles import oracle
from rmw_zenoh import Release, Robot
from ros_messages import S, ids_list, string, tf_message, transform, type_of, yaw_q

# -- people, without a network -------------------------------------------------------------


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
        # no person manager: each body's results from its first pose (the wait for one
        # is tested in tests/ros2/test_people.py)
        settings = {"ros_join_wait_s": 0.0, **settings}
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
    # (--head-dwell-s; the defaults: sustained attention off, the soft vote on)
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
