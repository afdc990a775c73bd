"""The turn's read-only snapshot: what scenes, outputs and queries read, each part worked out
once and only when asked for."""

from __future__ import annotations

from facing_service.contract.keys import BodyRef
from facing_service.contract.levels import Level
from facing_service.contract.stamps import Time
from facing_service.core.snapshot import TurnSnapshot

from trackers import sample, tracker


def test_each_part_is_worked_out_once_and_reads_the_tracker_as_the_turn_left_it():
    t = tracker()
    t.ingest([sample("a", sec=1), sample("b", off_deg=60.0, sec=2)], 0.0)
    snapshot = TurnSnapshot(t)
    assert [s.body_id for s in snapshot.states] == ["a", "b"] and snapshot.states is snapshot.states
    (frame,) = snapshot.frames
    assert frame.bodies_facing == ["a"] and snapshot.tracked == {"cam": 2}
    assert snapshot.levels[BodyRef(frame_id="cam", body_id="a")] in Level
    assert snapshot.scenes == [] and snapshot.empty_scene("cam") is None  # no scenes given
    wider, _ = snapshot.evaluate(120.0)  # another cone, without touching what was decided
    assert [s.facing for s in wider] == [True, True]
    assert [s.facing for s in snapshot.states] == [True, False]


def test_people_are_the_frames_poses_and_their_newest_stamp():
    t = tracker()
    t.ingest([sample("a", sec=1, x=1.0), sample("b", sec=3, x=2.0)], 0.0)
    people, newest = TurnSnapshot(t).people("cam")
    assert sorted(p.id for p in people) == ["a", "b"] and newest == Time.of(3)
    assert TurnSnapshot(t).people("nowhere") == ([], Time(0))


def test_a_pose_with_a_stance_is_a_person_standing_there_looking_from_the_pose():
    """A ROS4HRI person's pose is its face; its body, where it stands, comes as
    the pose's stance: the scene stands them there and lets them look from the face."""
    from dataclasses import replace

    t = tracker()
    looking = sample("p", sec=1, x=2.0)
    body = ((2.2, 0.3, 0.0), (0.0, 0.0, 0.0, 1.0))
    t.ingest([replace(looking, pose=replace(looking.pose, stance=body))], 0.0)
    (person,) = TurnSnapshot(t).people("cam")[0]
    assert (person.translation, person.rotation) == body
    assert person.look == (looking.pose.translation, looking.pose.rotation)
