"""A misconfigured robot says why: each cause of "no results" becomes one log line and a
status finding within 5 s (before, each was silence, or a bare counter)."""

from __future__ import annotations

import logging
import threading
import time

import pytest

from facing_service.contract.stamps import Time
from facing_service.core.tf.geometry import RigidTransform
from facing_service.ros2 import types as ros2_types
from facing_service.ros2.diagnosis import RobotWatch, where_else
from facing_service.ros2.people import People, TfInput
from facing_service.ros2.wire import RosFormat, Wire

import rmw_zenoh
from loopback import endpoint
from rmw_zenoh import Robot
from ros_messages import S, ids_list, tf_message, transform, yaw_q

TF, IDS = ros2_types.TF_MESSAGE, ros2_types.IDS_LIST


def tf_in(parent: str, child: str, sec: float) -> TfInput:
    return TfInput(
        parent, child, Time(int(sec * S)), RigidTransform((1.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
    )


# -- the checks, without a network -------------------------------------------------------


def test_where_else_names_the_settings_that_would_read_a_key():
    wire = Wire()
    rmw = "3/bot1/tf/tf2_msgs::msg::dds_::TFMessage_/RIHS01_" + "e" * 64
    assert where_else(wire, rmw) == "--ros-domain-id 3, --ros-namespace 'bot1'"
    assert where_else(wire, "bot2/tf") == "--ros-format bridge, --ros-namespace 'bot2'"
    bridge = Wire(RosFormat.BRIDGE)
    assert where_else(bridge, "0/tf/tf2_msgs::msg::dds_::TFMessage_/x") == "--ros-format rmw_zenoh"
    assert where_else(wire, "0/tf/tf2_msgs::msg::dds_::TFMessage_/x") == (
        "a type hash that is neither RIHS01 nor TypeHashNotSupported"
    )


def test_findings_wait_for_the_grace_then_name_the_cause():
    people = People("base_link")
    watch = RobotWatch(Wire(), started=0.0)
    assert watch.findings(people, now=1.0) == {}  # a robot gets 2 s to say something
    assert list(watch.findings(people, now=2.5)) == ["no_ros_input"]
    people.on_tf([tf_in("camera_link", "face_f1", 1), tf_in("map", "x", 1)], static=False)
    watch.on_input("/tf")
    (line,) = watch.findings(people, now=3.0).values()
    assert "base frame 'base_link' is not in the robot's TF tree" in line
    assert "'camera_link' (2 frames)" in line and "'map' (2 frames)" in line


def test_tracked_people_whose_frames_never_reach_the_base_frame():
    people = People("base_link")
    people.on_tracked("/humans/bodies/tracked", ["a", "b"])
    people.on_tf([tf_in("base_link", "odom", 1), tf_in("map", "body_a", 1)], static=False)
    watch = RobotWatch(Wire(), started=0.0)
    watch.on_input("/tf")
    # a list leads its /tf by a moment: nothing said until a frame has been missing 2 s
    # (before, a second replay warned of its new ids before their /tf was read)
    assert watch.findings(people, now=5.0) == {}
    found = watch.findings(people, now=7.0)
    assert "body_b" in found["tracked_frames_missing"]
    assert found["people_not_connected"] == (
        "the frames of tracked people, body_a, are in the tree of 'map', and base frame "
        "'base_link' in that of 'base_link': nothing links the two trees"
    )


def test_time_going_back_clears_the_buffer_as_tfs_listener_does():
    people = People("base_link")
    people.on_tracked("/humans/bodies/tracked", ["a"])
    for i in range(30):
        update = people.on_tf([tf_in("base_link", "body_a", 10 + i / 30)], static=False)
    assert update.poses
    # The recording starts again: three messages in a row, every transform 1 s older.
    # The first two are held while that is told (before, both were refused as
    # tf_repeated_data, a WARNING on every second replay), then are the new timeline's.
    first = people.on_tf([tf_in("base_link", "body_a", 10)], static=False)
    second = people.on_tf([tf_in("base_link", "body_a", 10 + 1 / 30)], static=False)
    assert first.refused + second.refused == [] and first.poses + second.poses == []
    third = people.on_tf([tf_in("base_link", "body_a", 10 + 2 / 30)], static=False)
    assert third.time_back_ns == pytest.approx(0.9 * S, abs=0.05 * S)
    assert third.lost == ["body_a"] and [p.pose.stamp for p in third.poses] == [
        Time.of(10, 0),
        Time.of(10, 33333333),
        Time.of(10, 66666666),
    ]


def test_one_stale_message_between_fresh_ones_clears_nothing():
    people = People("base_link")
    people.on_tracked("/humans/bodies/tracked", ["a"])
    for i in range(60):
        stamp = 10 + i / 30
        back = people.on_tf([tf_in("base_link", "body_a", stamp - 1.5)], static=False)
        assert back.time_back_ns == 0
        people.on_tf([tf_in("base_link", "body_a", stamp)], static=False)


ROBOT, STRANGER = bytes(16), bytes(range(16))


def streaming(people, seconds, start=10.0, publisher=ROBOT, rate=30, attack=None):
    """The robot streams body_a at ``rate`` Hz, received at its stamps' time (the
    caller's clock equals the stamps here); ``attack(t)`` runs between messages."""
    updates = []
    for i in range(int(seconds * rate)):
        t = start + i / rate
        tf = [tf_in("base_link", "body_a", t)]
        updates.append(people.on_tf(tf, static=False, publisher=publisher, received_s=t))
        if attack is not None:
            updates += attack(t)
    return updates


def test_forged_stale_bursts_never_clear_the_buffer_while_the_robot_streams():
    """Three messages re-sending the body 5 s in the past, three bursts a second, from a
    stranger (and as well with the robot's own GID): each burst used to clear the TF
    buffer and lose everyone. A burst cannot span TIME_BACK_SPAN_S while the robot
    streams, so nothing is cleared and nobody is lost."""
    for forged_as in (STRANGER, ROBOT):
        people = People("base_link")
        people.on_tracked("/humans/bodies/tracked", ["a"])

        def burst(t, forged_as=forged_as, people=people):
            if round(t * 30) % 10:
                return []
            stale = [tf_in("base_link", "body_a", t - 5.0)]
            return [
                people.on_tf(stale, static=False, publisher=forged_as, received_s=t + k * 1e-4)
                for k in range(3)
            ]

        updates = streaming(people, 4.0, attack=burst)
        assert not any(u.time_back_ns or u.lost for u in updates)
        assert people.clears == 0
        assert sum(bool(u.poses) for u in updates) == 120  # every pose of the robot's


def test_a_replay_started_again_clears_once_and_a_flood_of_rewinds_is_refused():
    """One publisher going back for TIME_BACK_SPAN_S is a clock that went back: cleared,
    counted. Going back again within CLEAR_MIN_INTERVAL_S is refused and counted."""
    people = People("base_link")
    people.on_tracked("/humans/bodies/tracked", ["a"])
    streaming(people, 2.0, start=10.0)
    cleared = [u for u in streaming(people, 0.5, start=10.0) if u.time_back_ns]  # again
    assert len(cleared) == 1 and cleared[0].lost == ["body_a"]
    assert (people.clears, people.clears_refused) == (1, 0)
    # received later than the stamps say: the same rewind again, 1 s after the clear
    for i in range(15):
        people.on_tf([tf_in("base_link", "body_a", 9.0 + i / 30)], static=False,
                     publisher=ROBOT, received_s=11.0 + i / 30)  # fmt: skip
    assert (people.clears, people.clears_refused) == (1, 1)


def test_stale_messages_from_two_publishers_in_turn_are_two_runs():
    people = People("base_link")
    people.on_tracked("/humans/bodies/tracked", ["a"])
    streaming(people, 1.0)
    for i in range(30):  # a second apart each, but never three in a row from one
        who = (ROBOT, STRANGER)[i % 2]
        back = people.on_tf([tf_in("base_link", "body_a", 5.0)], static=False, publisher=who,
                            received_s=12.0 + i)  # fmt: skip
        assert back.time_back_ns == 0
    assert people.clears == 0


# -- end to end: the service tells, in its log and status ------------------------------------


@pytest.fixture
def site(net):
    router = net.router()
    ep = endpoint(router.port)
    robots: list[Robot] = []

    def robot(release=rmw_zenoh.JAZZY_0_2_10, **where) -> Robot:
        made = Robot(net.client(ep, mode="client"), release, **where)
        robots.append(made)
        return made

    yield ep, robot
    for made in robots:
        made.close()


def said_within(service, caplog, code: str, seconds: float = 5.0) -> str:
    """The finding ``code``, once both the status and the log say it."""
    deadline = time.monotonic() + seconds
    while True:
        ros2 = service.status().ros2
        logged = [r.getMessage() for r in caplog.records if f"[{code}]" in r.getMessage()]
        if ros2 is not None and code in ros2.findings and logged:
            assert len(logged) == 1, logged  # said once, not every second
            return ros2.findings[code]
        assert time.monotonic() < deadline, f"no {code} in {seconds} s: {ros2}"
        time.sleep(0.1)


def stream(robot: Robot, frames: list[tuple[str, str]], seconds: float, start: int = 10) -> None:
    for i in range(int(seconds * 30)):
        stamp = start * S + i * (S // 30)
        message = tf_message(
            *(transform(p, c, stamp, (2.0, 0.0, 0.0), yaw_q(180)) for p, c in frames)
        )
        robot.publish("/tf", TF, message)
        time.sleep(1 / 30)


@pytest.mark.parametrize(
    ("where", "hint"),
    [
        ({"domain": 3}, "--ros-domain-id 3"),
        ({"namespace": "bot1"}, "--ros-namespace 'bot1'"),
        ({"release": rmw_zenoh.BRIDGE_1_10_0}, "--ros-format bridge"),
    ],
    ids=["domain", "namespace", "format"],
)
def test_ros_data_elsewhere_names_the_setting(net, site, caplog, where, hint):
    caplog.set_level(logging.INFO, "facing_service")
    ep, make_robot = site
    service = net.robot_service(ep, base_frame="base_link")
    robot = make_robot(**where)
    stream(robot, [("base_link", "body_a")], 0.5)
    line = said_within(service, caplog, "ros_input_elsewhere")
    assert hint in line and "no /tf on 0/tf/" in line


def test_nothing_at_all_says_so(net, site, caplog):
    caplog.set_level(logging.INFO, "facing_service")
    ep, _ = site
    service = net.robot_service(ep, base_frame="base_link")
    assert "is the robot's router reachable" in said_within(service, caplog, "no_ros_input")


def test_a_base_frame_missing_from_the_tree_names_the_roots(net, site, caplog):
    caplog.set_level(logging.INFO, "facing_service")
    ep, make_robot = site
    service = net.robot_service(ep, base_frame="base_link")
    robot = make_robot()
    robot.publish("/humans/bodies/tracked", IDS, ids_list(["a"]))
    stream(robot, [("camera_link", "body_a")], 0.5)
    line = said_within(service, caplog, "base_frame_not_in_tree")
    assert "roots are 'camera_link' (2 frames)" in line and "--base-frame" in line
    assert service.status().counters["tf_lookups_unresolved"] > 0  # was all one could see


def test_people_in_another_tree_say_so(net, site, caplog):
    caplog.set_level(logging.INFO, "facing_service")
    ep, make_robot = site
    service = net.robot_service(ep, base_frame="base_link")
    robot = make_robot()
    robot.publish("/humans/bodies/tracked", IDS, ids_list(["a"]))
    stream(robot, [("base_link", "odom"), ("map", "body_a")], 0.5)
    assert "nothing links the two trees" in said_within(service, caplog, "people_not_connected")


def test_a_second_replay_clears_the_buffer_and_results_come_back(net, site, caplog):
    caplog.set_level(logging.INFO, "facing_service")
    ep, make_robot = site
    service = net.robot_service(ep, base_frame="base_link")
    consumer = net.client(ep, mode="client")
    results = net.recorder(consumer, "hri/bodies/body_a/facing/base_link")
    robot = make_robot()
    robot.publish("/humans/bodies/tracked", IDS, ids_list(["a"]))
    stream(robot, [("base_link", "body_a")], 1.0)
    stream(robot, [("base_link", "body_a")], 1.0)  # the same stamps again
    assert "went back by" in said_within(service, caplog, "time_went_back")
    stamps = [
        (i.value["stamp"]["sec"], i.value["stamp"]["nanosec"])
        for i in results.items
        if i.kind == "put"
    ]
    restarts = [i for i in range(1, len(stamps)) if stamps[i] < stamps[i - 1]]
    assert len(restarts) == 1, "results resume with the new times"
    assert any(i.kind == "delete" for i in results.items)  # lost, then back


def test_inspect_shows_what_the_robot_publishes_and_the_flags_that_read_it(net, site, capsys):
    from facing_service.config.settings import Settings
    from facing_service.tools.inspect import inspect_robot

    ep, make_robot = site
    robot = make_robot(rmw_zenoh.HUMBLE_0_1_9, domain=3, namespace="bot1")
    robot.publish("/tf_static", TF, tf_message(transform("map", "camera", 0)), latched=True)
    robot.publish("/humans/bodies/tracked", IDS, ids_list(["a", "b"]))
    settings = Settings(mode="client", connect=[ep], no_multicast_scouting=True)
    done: list[int] = []
    listener = threading.Thread(
        target=lambda: done.append(inspect_robot(settings, 1.5, "base_link"))
    )
    listener.start()
    stream(robot, [("camera", "body_a")], 1.2)
    robot.publish("/humans/bodies/tracked", IDS, ids_list(["a", "b"]))
    listener.join(timeout=10)
    assert done == [0]
    out = capsys.readouterr().out
    assert "rmw_zenoh, domain 3, namespace bot1, Humble (keys carry TypeHashNotSupported)" in out
    assert "map  (root)" in out and "camera  (static)" in out and "body_a  (" in out
    assert "/humans/bodies/tracked: a, b" in out
    assert "base frame 'base_link' is not in the TF tree" in out
    assert (
        f"facing-service run --input ros2 -m client -e {ep} --no-multicast-scouting "
        "--ros-format rmw_zenoh --ros-domain-id 3 --ros-namespace bot1 --base-frame map"
    ) in out  # the session flags inspect was given carry into the command it suggests


def chain_message(links: int, name=lambda i: f"link{i}") -> bytes:
    chain = [transform(name(i), name(i + 1), 10 * S) for i in range(links)]
    return tf_message(*chain)


def surveyed(samples) -> list[str]:
    from facing_service.tools.inspect import Survey

    survey = Survey()
    for key, payload in samples:
        survey.on_sample(key, payload, None, 1.0)
    return survey.report("base_link", 2.0)


def test_inspect_walks_a_1500_link_chain_without_recursion_into_a_bounded_report():
    from facing_service.tools.inspect import TREE_LINES

    lines = surveyed([("tf", chain_message(1500))])
    assert len(lines) < TREE_LINES + 40
    assert any("more frame(s)" in line for line in lines)
    assert max(map(len, lines)) < 300


def test_inspect_names_every_place_of_tf_instead_of_picking_the_first():
    """20 000 namespaces carrying /tf printed 40 000 lines and recommended the attacker's
    --ros-namespace ns0: now at most KEYS_KEPT keys are kept, the rest counted, and the
    flags are given for each place, the choice left to the user."""
    one = tf_message(transform("base_link", "body_a", 10 * S))
    lines = surveyed([(f"ns{i}/tf", one) for i in range(20_000)])
    assert len(lines) < 200
    text = "\n".join(lines)
    assert "/tf is published in 20000 places" in text
    assert "more key(s), not listed" in text
    assert text.count("facing-service run") == 5


def test_inspect_cuts_names_a_sender_chose():
    huge = "x" * 200_000
    one = tf_message(transform("base_link", "body_a", 10 * S), transform("body_a", huge, 10 * S))
    lines = surveyed([("tf", one), ("humans/bodies/tracked", ids_list(["a" * 100_000]))])
    assert max(map(len, lines)) < 300
    assert any("names over 256 characters" in line for line in lines)


def test_inspect_exits_0_on_a_robot_publishing_a_1500_link_chain(net, site, capsys):
    from facing_service.config.settings import Settings
    from facing_service.tools.inspect import inspect_robot

    ep, make_robot = site
    robot = make_robot(rmw_zenoh.JAZZY_0_2_10)
    settings = Settings(mode="client", connect=[ep], no_multicast_scouting=True)
    done: list[int] = []
    listener = threading.Thread(target=lambda: done.append(inspect_robot(settings, 1.0, "link0")))
    listener.start()
    for _ in range(5):
        robot.publish("/tf", TF, chain_message(1500))
        time.sleep(0.1)
    listener.join(timeout=20)
    assert done == [0]
    out = capsys.readouterr().out.splitlines()
    assert len(out) < 300 and any("more frame(s)" in line for line in out)


def test_inspect_pointed_at_a_router_suggests_the_isolated_way_to_join_it():
    """A defect found: `inspect -e tcp/localhost:7447` suggested a plain peer, which scouts by
    multicast and listens everywhere, against the README's isolation advice."""
    from facing_service.config.settings import Settings
    from facing_service.tools.inspect import session_flags

    plain = Settings(connect=["tcp/localhost:7447"])
    assert session_flags(plain) == "-m client -e tcp/localhost:7447 --no-multicast-scouting"
    peer = Settings(mode="peer", connect=["tcp/localhost:7447"])
    assert session_flags(peer) == "-m peer -e tcp/localhost:7447"  # as the user said it
    assert session_flags(Settings()) == ""
