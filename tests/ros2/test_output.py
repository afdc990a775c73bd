"""ROS 2 output: our results on the robot's own topics, checked by independent
implementations of the wire: zenoh-ros2-sdk (its own rmw_zenoh keys, type hashes,
attachments and liveliness parsing) and rosbags (its own CDR)."""

from __future__ import annotations

import json
import threading
import time
from pathlib import Path
from types import SimpleNamespace

import pytest
import zenoh

from facing_service.config.settings import Settings
from facing_service.contract.keys import BodyRef
from facing_service.contract.poses import Stamp
from facing_service.contract.schemas import FrameFacing
from facing_service.contract.stamps import Time
from facing_service.core.engagement import Level, Zone
from facing_service.core.records import Changes, EngagementUpdate
from facing_service.ros2 import types as ros2_types
from facing_service.ros2.output import (
    ENGAGEMENT_LEVEL,
    INTENT,
    RosMessage,
    RosOutput,
    engage_intent,
)
from facing_service.ros2.wire import RosFormat, Wire
from facing_service.tools.replay import Replay

import rmw_zenoh
from bags import messages
from loopback import endpoint
from oracles import BAGS
from poses import pose_json
from rmw_zenoh import JAZZY_0_2_10 as JAZZY
from upstream import STANDARD_MSGS, definition

pytestmark = pytest.mark.slow  # processes, recordings or seconds-long scenarios


RECORDING = BAGS / "1p_AA_eng_1"  # one person, rorql, labelled ENGAGED
TWO_PEOPLE = BAGS / "2p_AA_FV_eng_1"  # eloek and ghfbv, both labelled ENGAGED
# -- types and messages, without a network -----------------------------------------------


def update(body: str, level: Level, previous: Level | None) -> EngagementUpdate:
    return EngagementUpdate(
        BodyRef(frame_id="base_link", body_id=body),
        Time.of(5),
        level,
        0.9,
        Zone.SOCIAL,
        Time.of(4),
        previous,
    )


def test_levels_go_out_on_change_and_on_every_tick_like_hri_engagement():
    out = RosOutput(rate_hz=10.0, intents=True)
    changes = Changes(
        engagement=[
            update("person_p1", Level.ENGAGED, Level.ENGAGING),
            update("body_b1", Level.ENGAGED, Level.ENGAGING),  # not a person: no topic
        ]
    )
    messages = out.on_changes(changes)
    assert [m.topic for m in messages] == ["/humans/persons/p1/engagement_status", "/intents"]
    status = ros2_types.deserialize(messages[0].payload, ENGAGEMENT_LEVEL)
    assert status.level == 3 and status.header.stamp.sec == 5
    intent = ros2_types.deserialize(messages[1].payload, INTENT)
    assert intent.intent == "__intent_engage_with__"
    assert json.loads(intent.data) == {"recipient": "p1"}
    tracked = [update("person_p1", Level.ENGAGED, None), update("face_f1", Level.ENGAGED, None)]
    snapshot = SimpleNamespace(
        engagements=tracked, levels={}, states=[], scenes=[]
    )  # nobody to draw
    first = out.tick(0.0, snapshot)
    assert [m.topic for m in first] == ["/humans/persons/p1/engagement_status"]
    assert out.tick(0.05, snapshot) == []  # not due before 1/10 s
    assert len(out.tick(0.1, snapshot)) == 1


def test_a_lost_person_is_said_unknown_once_and_its_topic_goes():
    out = RosOutput(rate_hz=10.0, intents=False)
    lost = out.on_changes(Changes(engagement=[update("person_p1", Level.UNKNOWN, Level.ENGAGED)]))
    assert [(m.topic, m.payload is None) for m in lost] == [
        ("/humans/persons/p1/engagement_status", False),
        ("/humans/persons/p1/engagement_status", True),  # undeclare
    ]
    assert ros2_types.deserialize(lost[0].payload, ENGAGEMENT_LEVEL).level == 0


def test_facing_lists_per_kind():
    frame = FrameFacing(
        frame_id="base_link",
        stamp=Stamp(sec=7, nanosec=0),
        bodies_facing=["body_b1", "face_f1", "person_p1", "plain"],
        bodies_tracked=[],
    )
    out = RosOutput(10.0, False)
    messages = out.on_changes(Changes(frames=[frame]))
    lists = {m.topic: ros2_types.deserialize(m.payload, ros2_types.IDS_LIST).ids for m in messages}
    assert lists == {
        "/humans/bodies/facing": ["b1", "plain"],
        "/humans/faces/facing": ["f1"],
        "/humans/persons/facing": ["p1"],
    }
    assert engage_intent("p1").typename == INTENT
    # Said when a set changes, not whenever the frame's aggregate does (docs/ros2.md).
    later = frame.model_copy(update={"stamp": Stamp(sec=8, nanosec=0), "bodies_tracked": ["x"]})
    assert out.on_changes(Changes(frames=[later])) == []
    fewer = later.model_copy(update={"bodies_facing": ["body_b1", "plain", "person_p1"]})
    (changed,) = out.on_changes(Changes(frames=[fewer]))
    assert changed.topic == "/humans/faces/facing"
    assert ros2_types.deserialize(changed.payload, ros2_types.IDS_LIST).ids == []


# -- end to end: a real recording through the service, read back by others ------------------


@pytest.fixture
def sdk(tmp_path, monkeypatch, net):
    """zenoh-ros2-sdk, offline (message definitions from a local folder) and on loopback
    (its singleton session closed afterwards)."""
    from zenoh_ros2_sdk import message_registry
    from zenoh_ros2_sdk.session import ZenohSession

    folder = tmp_path / "msgs"
    for typename, text in {
        **STANDARD_MSGS,
        ENGAGEMENT_LEVEL: definition(ENGAGEMENT_LEVEL),
        ros2_types.IDS_LIST: definition(ros2_types.IDS_LIST),
    }.items():
        package, kind, name = typename.split("/")
        (folder / package / kind).mkdir(parents=True, exist_ok=True)
        (folder / package / kind / f"{name}.msg").write_text(text)
    monkeypatch.setattr(
        message_registry, "_registry", message_registry.MessageRegistry(str(folder))
    )
    monkeypatch.setenv(
        "ZENOH_CONFIG_OVERRIDE", 'mode="client";scouting/multicast/enabled=false;scouting/delay=0'
    )
    yield
    if ZenohSession._instance is not None:
        ZenohSession._instance.close()
        ZenohSession._instance = None


def run_recording(net, fmt: RosFormat, recording: Path = RECORDING, **settings):
    """A router, the service with ROS 2 input and output, and the recording replayed."""
    router = net.router()
    ep = endpoint(router.port)
    service = net.robot_service(
        ep, output="ros2", ros_format=fmt.value, base_frame="camera_link", **settings
    )
    robot = net.client(ep, mode="client")

    def play() -> None:
        time.sleep(0.5)  # subscribers of the caller get declared and propagated
        with Replay(robot, recording, Wire(fmt)) as replay:
            replay.run(rate=4.0)

    return router.port, service, play


@pytest.mark.shared_data
def test_rmw_zenoh_subscribers_get_engagement_status_with_valid_attachments(net, sdk):
    from zenoh_ros2_sdk import ROS2Subscriber
    from zenoh_ros2_sdk.discovery import get_topic_names_and_types
    from zenoh_ros2_sdk.session import ZenohSession

    port, _service, play = run_recording(net, RosFormat.RMW_ZENOH, TWO_PEOPLE, ros_intents=True)
    topic = "/humans/persons/eloek/engagement_status"
    store = ZenohSession.get_instance("127.0.0.1", port)
    for typename in ("builtin_interfaces/msg/Time", "std_msgs/msg/Header"):  # nested types
        store.register_message_type(STANDARD_MSGS[typename], typename)
    seen: dict[str, list[int]] = {"eloek": [], "ghfbv": []}
    for person, person_levels in seen.items():  # the SDK's session owns them (fixture)
        ROS2Subscriber(
            f"/humans/persons/{person}/engagement_status",
            ENGAGEMENT_LEVEL,
            lambda message, into=person_levels: into.append(message.level),
            msg_definition=definition(ENGAGEMENT_LEVEL),
            router_port=port,
        )
    levels = seen["eloek"]
    raw: list[zenoh.Sample] = []
    lock = threading.Lock()
    consumer = net.client(endpoint(port), mode="client")

    def keep(sample: zenoh.Sample) -> None:
        with lock:
            raw.append(sample)

    net_sub = consumer.declare_subscriber(Wire().key(topic, ENGAGEMENT_LEVEL), keep)
    try:
        play()
        deadline = time.monotonic() + 10
        while Level.ENGAGED not in levels and time.monotonic() < deadline:
            time.sleep(0.05)
        assert Level.ENGAGED in levels, f"the SDK subscriber saw {levels}"
        assert all(seen.values()), f"a listed person got no engagement_status: {seen}"
        # The graph, as `ros2 topic list` / `ros2 node list` build it from liveliness.
        topics = dict(get_topic_names_and_types(0, router_port=port, timeout=2.0))
        assert ENGAGEMENT_LEVEL in topics.get(topic, []), topics  # our publisher's token
        nodes = [
            str(r.ok.key_expr)
            for r in consumer.liveliness().get("@ros2_lv/0/**", timeout=2)
            if r.ok is not None and "/NN/" in str(r.ok.key_expr)
        ]
        assert any(n.endswith("/facing_service") for n in nodes), nodes
    finally:
        net_sub.undeclare()
    with lock:
        samples = list(raw)
    numbers = []
    for sample in samples:
        decoded = ros2_types.deserialize(sample.payload.to_bytes(), ENGAGEMENT_LEVEL)  # rosbags
        assert decoded.level in {int(level) for level in Level}
        # zenoh-ros2-sdk's parser, and the 33 bytes of rmw_zenoh since Jazzy 0.2.4
        number, _gid = rmw_zenoh.parse_attachment(JAZZY, sample.attachment.to_bytes())
        numbers.append(number)
    assert numbers and numbers == list(range(numbers[0], numbers[0] + len(numbers)))
    assert numbers[0] == 1  # from 1 per publisher
    # The SDK's subscriber decoded the very messages the raw one saw, in order.
    raw_levels = [
        ros2_types.deserialize(s.payload.to_bytes(), ENGAGEMENT_LEVEL).level for s in samples
    ]
    common = min(len(levels), len(raw_levels))
    assert levels[:common] == raw_levels[:common] and Level.ENGAGED in levels[:common]


@pytest.mark.shared_data
def test_bridge_subscribers_get_engagement_status_as_raw_cdr(net):
    port, _service, play = run_recording(net, RosFormat.BRIDGE)
    consumer = net.client(endpoint(port), mode="client")
    samples = net.recorder(consumer, "humans/persons/rorql/engagement_status")
    facing = net.recorder(consumer, "humans/persons/facing")
    play()
    samples.wait_for(
        lambda i: ros2_types.deserialize(i.payload, ENGAGEMENT_LEVEL).level == Level.ENGAGED
    )
    # One story for heads: rorql, who engages, is on the persons' facing list meanwhile.
    (listed,) = facing.wait_for(
        lambda i: "rorql" in ros2_types.deserialize(i.payload, ros2_types.IDS_LIST).ids
    )
    assert ros2_types.deserialize(listed.payload, ros2_types.IDS_LIST).header.frame_id == (
        "camera_link"
    )


@pytest.mark.shared_data
def test_replay_records_what_the_service_published(net, tmp_path):
    """--record: the service's ROS 2 output written into a bag that ROS tools (and
    rosbags) open afterwards."""
    from facing_service.testing import LOOPBACK_FLAGS, running_cli

    router = net.router()
    ep = endpoint(router.port)
    net.robot_service(ep, output="ros2", base_frame="camera_link")
    out = tmp_path / "run"
    flags = ("--rate", "4", "--record", str(out), "-m", "client", "-e", ep, *LOOPBACK_FLAGS)
    with running_cli("replay", str(RECORDING), *flags) as proc:
        assert proc.wait(timeout=60) == 0, proc.stdout.read()
        output = proc.stdout.read()
    assert "recorded" in output
    levels = [
        message.level
        for topic, _, _, message in messages(out)
        if topic == "/humans/persons/rorql/engagement_status"
    ]
    assert Level.ENGAGED in levels
    assert Path(out, "metadata.yaml").is_file()


@pytest.mark.shared_data
def test_a_recording_written_as_mcap_replays(net, tmp_path):
    """--record OUT.mcap writes an mcap bag; replay reads it back (both storage formats
    rosbag2 uses: the shared recordings are sqlite3)."""
    from facing_service.tools.record import Recording

    router = net.router()
    ep = endpoint(router.port)
    net.robot_service(ep, output="ros2", base_frame="camera_link")
    robot = net.client(ep, mode="client")
    out = tmp_path / "run.mcap"
    recording = Recording(robot, Wire(), out)
    time.sleep(0.5)
    with Replay(robot, RECORDING, Wire()) as replay:
        replay.run(rate=4.0)
    time.sleep(0.5)
    recorded, _ = recording.close()
    (bag,) = [p for p in tmp_path.iterdir() if p.name.startswith("run")]
    assert list(bag.glob("*.mcap"))
    levels = [
        message.level
        for topic, _, _, message in messages(bag)
        if topic == "/humans/persons/rorql/engagement_status"
    ]
    assert Level.ENGAGED in levels  # what the service said is in the bag
    with Replay(robot, bag, Wire(RosFormat.BRIDGE)) as replay:
        stats = replay.run(rate=50.0)
    assert stats.messages == recorded


def test_where_to_stand_goes_out_as_pose_stamped_and_its_topic_goes_with_it():
    """Where to stand, on a ROS 2 robot: the place to join a group the robot is not in, as a
    geometry_msgs/PoseStamped in the base frame (a navigation goal as it is), every period
    while the group has room; its publisher undeclared once the group is gone."""
    from facing_service.config.profiles import scene_params, tracker_for
    from facing_service.contract.keys import BodyRef
    from facing_service.contract.poses import decode_pose
    from facing_service.core.records import PoseSample
    from facing_service.core.snapshot import TurnSnapshot
    from facing_service.core.social.scene import Scenes
    from facing_service.ros2.output import POSE_STAMPED, RosOutput

    settings = Settings(base_frame="base_link", group_hold_s=0.0)
    tracker, scenes = tracker_for(settings), Scenes(scene_params(settings))
    people = {"ann": (3.0, 0.6, -90.0), "bob": (3.0, -0.6, 90.0)}
    for name, (x, y, yaw) in people.items():
        raw = pose_json(name, "base_link", x=x, y=y, yaw_deg=yaw)
        pose = decode_pose(raw, name, "base_link", 1 << 16)
        tracker.ingest([PoseSample(BodyRef(frame_id="base_link", body_id=name), pose)], 0.0)
    scenes.touch({"base_link"})
    scenes.tick(0.0, TurnSnapshot(tracker, scenes))
    out = RosOutput(rate_hz=10.0, intents=False)
    (join,) = [
        m for m in out.tick(1.0, TurnSnapshot(tracker, scenes)) if m.typename == POSE_STAMPED
    ]
    assert join.topic.startswith("/humans/interactions/groups/") and join.topic.endswith("/join")
    message = ros2_types.deserialize(join.payload, POSE_STAMPED)
    assert message.header.frame_id == "base_link"
    assert message.pose.position.x < 3.0 and abs(message.pose.position.y) < 0.3
    assert abs(message.pose.orientation.z) < 0.1  # facing +x, into the group
    tracker.lose([BodyRef(frame_id="base_link", body_id="bob")], 2.0)
    scenes.touch({"base_link"})
    scenes.tick(2.0, TurnSnapshot(tracker, scenes))
    gone = [m for m in out.tick(2.0, TurnSnapshot(tracker, scenes)) if m.typename == POSE_STAMPED]
    assert gone == [RosMessage(join.topic, POSE_STAMPED, None)]
