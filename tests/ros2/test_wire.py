"""The robot's wire forms: keys in both formats, type hashes, attachments in both layouts, the
form learned from what the robot sends (ros2/wire)."""

from __future__ import annotations

import logging

import pytest

from facing_service.ros2 import types as ros2_types
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

# -- keys and attachments ---------------------------------------------------------------


TF_HASH = "RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087"


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
