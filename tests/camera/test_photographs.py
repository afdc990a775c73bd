"""Real faces, in scikit-image's sample photographs (``astronaut``: Eileen Collins, frontal;
``camera``: the cameraman, turned away in three-quarter view), through MediaPipe and the fit:
the frontal face faces the camera, the turned one does not, a mirror flips the sign of the
angle, a face half the size is twice as far, five faces at once are all found."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip(
    "mediapipe", reason="the camera extra is not installed: its tests run in .venv-camera (README)"
)
import cv2
import skimage.data

from facing_service.camera import frames
from facing_service.camera.face_model import face_model
from facing_service.camera.head_pose import HeadPose, fit_head
from facing_service.camera.intrinsics import from_field_of_view
from facing_service.camera.landmarks import FaceMesh
from facing_service.core.detector import classify_one, robot_in_body

FRAME = (480, 640)


@pytest.fixture(scope="module")
def mesh():
    found = FaceMesh(max_faces=5)
    yield found
    found.close()


def photo(name: str) -> np.ndarray:
    image = getattr(skimage.data, name)()
    return np.ascontiguousarray(np.stack([image] * 3, -1) if image.ndim == 2 else image)


def on_frame(image: np.ndarray, scale: float = 1.0) -> np.ndarray:
    """``image`` scaled by ``scale`` and centred on a 640x480 frame: the camera's frame
    stays the same, the face in it changes size, not direction."""
    return frames.on_frame(image, FRAME[1], FRAME[0], scale)


def heads(mesh: FaceMesh, frame: np.ndarray) -> list[HeadPose]:
    camera = from_field_of_view(frame.shape[1], frame.shape[0])
    found = [fit_head(landmarks, face_model(), camera) for landmarks in mesh(frame)]
    return [head for head in found if head is not None]


def signed_angle_deg(head: HeadPose) -> float:
    """Where the camera is as the face sees it: left of its nose positive."""
    r = robot_in_body(np.array([head.translation]), np.array([head.rotation]))[0]
    return math.degrees(math.atan2(r[1], r[0]))


def test_the_frontal_face_faces_the_camera_and_the_turned_one_does_not(mesh):
    (astronaut,) = heads(mesh, on_frame(photo("astronaut")))
    (cameraman,) = heads(mesh, on_frame(photo("camera")))
    _, frontal, _, facing = classify_one(astronaut.translation, astronaut.rotation, 20.0)
    assert facing and frontal < 10.0
    _, turned, _, facing = classify_one(cameraman.translation, cameraman.rotation, 20.0)
    assert not facing and turned > 40.0


def test_a_mirrored_photograph_flips_the_sign_of_the_angle(mesh):
    image = photo("camera")
    (plain,) = heads(mesh, on_frame(image))
    (mirrored,) = heads(mesh, on_frame(np.ascontiguousarray(image[:, ::-1])))
    assert abs(signed_angle_deg(plain)) > 40.0
    assert signed_angle_deg(mirrored) == pytest.approx(-signed_angle_deg(plain), abs=5.0)


def test_a_face_half_the_size_is_twice_as_far(mesh):
    image = photo("astronaut")
    (near,) = heads(mesh, on_frame(image, 0.9))
    (far,) = heads(mesh, on_frame(image, 0.45))
    ratio = np.linalg.norm(far.translation) / np.linalg.norm(near.translation)
    assert ratio == pytest.approx(2.0, rel=0.05)  # measured: 1.96


def test_five_faces_at_once_are_all_found(mesh):
    face = photo("astronaut")[0:320, 80:370]
    frame = np.full((*FRAME, 3), 110, np.uint8)
    for row, col in [(10, 10), (10, 225), (10, 440), (250, 115), (250, 330)]:
        frame[row : row + 210, col : col + 190] = cv2.resize(face, (190, 210))
    found = heads(mesh, frame)
    assert len(found) == 5
    assert all(classify_one(h.translation, h.rotation, 20.0)[3] for h in found)
