"""A face keeps its id while it moves a little, a new face gets a new one, a face unseen
for a moment is lost."""

from __future__ import annotations

from facing_service.camera.face_ids import FaceIds, FaceSeen


def test_a_face_moving_less_than_its_width_keeps_its_id():
    ids = FaceIds()
    assert ids.update([FaceSeen(100, 100, 80)], 0.0) == (["f1"], [])
    assert ids.update([FaceSeen(150, 110, 80)], 0.05) == (["f1"], [])


def test_a_face_further_than_its_width_is_someone_else():
    ids = FaceIds()
    ids.update([FaceSeen(100, 100, 80)], 0.0)
    named, lost = ids.update([FaceSeen(300, 100, 80)], 0.05)
    assert named == ["f2"] and lost == []


def test_two_faces_keep_theirs_nearest_first_whatever_their_order():
    ids = FaceIds()
    ids.update([FaceSeen(100, 100, 60), FaceSeen(400, 100, 60)], 0.0)
    named, _ = ids.update([FaceSeen(390, 105, 60), FaceSeen(110, 100, 60)], 0.05)
    assert named == ["f2", "f1"]


def test_a_face_unseen_for_longer_than_forget_s_is_lost_once_and_its_id_not_reused():
    ids = FaceIds(forget_s=0.5)
    ids.update([FaceSeen(100, 100, 80)], 0.0)
    assert ids.update([], 0.4) == ([], [])  # a missed frame or two: still held
    assert ids.update([], 0.6) == ([], ["f1"])
    assert ids.update([], 0.7) == ([], [])
    assert ids.update([FaceSeen(100, 100, 80)], 0.8) == (["f2"], [])
    assert ids.forget_all() == ["f2"] and ids.forget_all() == []


def test_a_prefix_keeps_two_cameras_ids_apart():
    left, right = FaceIds(prefix="left-"), FaceIds(prefix="right-")
    assert left.update([FaceSeen(100, 100, 80)], 0.0)[0] == ["left-1"]
    assert right.update([FaceSeen(100, 100, 80)], 0.0)[0] == ["right-1"]


def test_the_ids_given_are_counted_once_each():
    ids = FaceIds()
    ids.update([FaceSeen(100, 100, 80), FaceSeen(400, 100, 80)], 0.0)
    ids.update([FaceSeen(105, 100, 80)], 0.1)  # one of the two again: nothing new
    assert ids.given == 2
