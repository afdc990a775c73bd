"""People across the room: a frontal face 30 px wide in a 1280x720 frame (5 m
for a 65° camera) is found and said facing, a turned one at 3 m found and said not facing,
once the tiles have had their turn; faces near cost no tile; the tiles cover every frame."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

pytest.importorskip(
    "mediapipe", reason="the camera extra is not installed: its tests run in .venv-camera (README)"
)
import cv2
import skimage.data

from facing_service.camera.face_model import face_model
from facing_service.camera.frontend import FACE_WIDTH_M, tile_for
from facing_service.camera.head_pose import fit_head
from facing_service.camera.intrinsics import from_field_of_view
from facing_service.camera.landmarks import FaceMesh, tiles
from facing_service.core.detector import classify_one

CAMERA = from_field_of_view(1280, 720, 65.0)
#: The astronaut's face is 104 px wide (the detector's box) in this crop of her photo.
ASTRONAUT, ASTRONAUT_FACE_PX = (0, 320, 80, 370), 104.0
#: The cameraman's, in three-quarter view: 76 px.
CAMERAMAN, CAMERAMAN_FACE_PX = (50, 300, 120, 360), 76.0


def at_distance(photo: np.ndarray, crop, face_px: float, metres: float, where) -> np.ndarray:
    """The face of ``photo`` as wide as a 15 cm face ``metres`` away, pasted at ``where``
    (shares of the frame) of a 1280x720 photograph of a coffee cup."""
    top, bottom, left, right = crop
    face = np.ascontiguousarray(photo[top:bottom, left:right])
    scale = FACE_WIDTH_M * CAMERA.fx / metres / face_px
    face = cv2.resize(face, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA)
    frame = cv2.resize(skimage.data.coffee(), (1280, 720))
    x, y = round(1280 * where[0] - face.shape[1] / 2), round(720 * where[1] - face.shape[0] / 2)
    frame[y : y + face.shape[0], x : x + face.shape[1]] = face
    return frame


def verdicts(frame: np.ndarray, reach_m: float | None, held: int = 8) -> list[bool]:
    """Facing or not, for each face found after ``held`` frames of the same picture
    (``reach_m`` None: the detector on the whole frame only, as before the tiling)."""
    mesh = FaceMesh(5, None if reach_m is None else tile_for(CAMERA, reach_m))
    try:
        for _ in range(held):
            found = mesh(frame)
    finally:
        mesh.close()
    heads = [fit_head(landmarks, face_model(), CAMERA) for landmarks in found]
    return [classify_one(h.translation, h.rotation, 20.0)[3] for h in heads if h is not None]


@pytest.mark.parametrize("where", [(0.2, 0.3), (0.5, 0.5), (0.85, 0.7)])
def test_a_frontal_face_five_metres_away_is_found_and_faces(where):
    """Before: the detector saw the frame at 192 px, the face at 4.5 px, and missed it."""
    frame = at_distance(skimage.data.astronaut(), ASTRONAUT, ASTRONAUT_FACE_PX, 5.0, where)
    assert verdicts(frame, reach_m=5.0) == [True]
    assert verdicts(frame, reach_m=None) == []  # the whole frame only: out of its reach


def test_a_turned_face_three_metres_away_is_found_and_does_not_face():
    """Beyond the whole frame's reach (2 m); at 55° turned, further than 3 m it is not
    found at all (docs/camera.md: what it cannot see)."""
    cameraman = np.stack([skimage.data.camera()] * 3, -1)
    frame = at_distance(cameraman, CAMERAMAN, CAMERAMAN_FACE_PX, 3.0, (0.6, 0.4))
    assert verdicts(frame, reach_m=5.0) == [False]
    assert verdicts(frame, reach_m=None) == []


def test_faces_near_cost_no_tile_and_a_longer_reach_smaller_tiles():
    assert tile_for(CAMERA, 1.5) is None  # the whole frame shows a face 1.5 m away
    five, eight = tile_for(CAMERA, 5.0), tile_for(CAMERA, 8.0)
    assert five is not None and eight is not None and eight < five
    assert five == pytest.approx(192 * (0.15 * CAMERA.fx / 5.0) / 15, abs=1)


@pytest.mark.parametrize(("width", "height", "side"), [(1280, 720, 386), (640, 480, 193),
                                                       (1280, 720, 241)])  # fmt: skip
def test_the_tiles_cover_the_frame_and_overlap_by_a_quarter(width, height, side):
    placed = tiles(width, height, side)
    covered = np.zeros((height, width), bool)
    for x, y, s in placed:
        assert x >= 0 and y >= 0 and x + s <= width and y + s <= height
        covered[y : y + s, x : x + s] = True
    assert covered.all()
    xs = sorted({x for x, _, _ in placed})
    assert all(b - a <= side * 3 // 4 for a, b in itertools.pairwise(xs))
    assert tiles(width, height, max(width, height)) == []
    assert math.isclose(len({y for _, y, _ in placed}) * len(xs), len(placed))


def test_the_command_line_reaches_as_far_as_the_front_end_by_default():
    from facing_service.arguments import CAMERA_DEFAULTS
    from facing_service.camera.frames import Source
    from facing_service.camera.frontend import DEFAULT_REACH_M, CameraOptions

    # None: the front end's default, unsaid where the frame cannot give it
    assert CAMERA_DEFAULTS["reach_m"] is None is CameraOptions(Source()).reach_m
    assert DEFAULT_REACH_M == 5.0


def test_a_reach_past_what_the_frame_shows_is_said_with_the_frames_limit():
    """A defect found: beyond about 5 m at 640x480 the tiles are the detector's own 192 px, so a
    longer --reach-m changed nothing and said nothing. The limit is where a face is the
    detector's smallest at that tile; asked past it, the front end says so, once."""
    from facing_service.camera.frontend import _short_reach, farthest_reach_m
    from facing_service.camera.intrinsics import from_field_of_view

    vga, hd = from_field_of_view(640, 480), from_field_of_view(1280, 720)
    assert farthest_reach_m(vga) == pytest.approx(5.02, abs=0.01)
    assert farthest_reach_m(hd) == pytest.approx(10.04, abs=0.01)
    assert tile_for(vga, farthest_reach_m(vga)) == 192  # exactly the detector's own side
    assert _short_reach(vga, 5.0) is None and _short_reach(hd, 8.0) is None
    said = _short_reach(vga, 8.0)
    assert said is not None and said.startswith("--reach-m 8 is past what 640x480 frames")
    assert "faces are looked for to 5.0 m" in said
