"""The fit recovers a head's pose from its landmarks and says it in the frames ROS uses: a
face looking into the camera faces it, one turned away does not, and a camera mounted on a
robot moves every pose with it. Landmarks are made by projecting the model with OpenCV's
own camera model at a known pose; scipy is the independent oracle of the rotations."""

from __future__ import annotations

import math

import numpy as np
import pytest

cv2 = pytest.importorskip(
    "cv2", reason="the camera extra is not installed: its tests run in .venv-camera (README)"
)
from scipy.spatial.transform import Rotation  # noqa: E402

from facing_service.camera.face_model import MODEL, canonical_vertices, face_model, in_face_frame  # noqa: E402
from facing_service.camera.head_pose import OPTICAL_TO_BODY, Mount, fit_head, quaternion_of  # noqa: E402
from facing_service.camera.intrinsics import from_field_of_view  # noqa: E402
from facing_service.core.detector import classify_one  # noqa: E402

CAMERA = from_field_of_view(640, 480, 65.0)
ALL = in_face_frame(canonical_vertices((MODEL / "canonical_face_model.obj").read_text()))


def landmarks_of(position_m: tuple[float, float, float], yaw_deg: float, pitch_deg: float = 0.0):
    """The 468 landmarks, in pixels, of the canonical face at ``position_m`` in camera_link
    (x forward), turned by ``yaw_deg`` from looking straight back at the camera."""
    face_in_body = Rotation.from_euler("ZY", [180.0 + yaw_deg, pitch_deg], degrees=True)
    in_optical = OPTICAL_TO_BODY.T @ face_in_body.as_matrix()
    rvec, _ = cv2.Rodrigues(in_optical)
    tvec = OPTICAL_TO_BODY.T @ np.array(position_m)
    matrix = np.array([[CAMERA.fx, 0, CAMERA.cx], [0, CAMERA.fy, CAMERA.cy], [0, 0, 1.0]])
    points, _ = cv2.projectPoints(ALL, rvec, tvec, matrix, None)
    return points[:, 0, :], face_in_body


@pytest.mark.parametrize("yaw_deg", [-60.0, -25.0, 0.0, 10.0, 45.0])
@pytest.mark.parametrize("position", [(0.6, 0.0, 0.0), (1.5, 0.3, -0.1), (3.0, -0.5, 0.2)])
def test_the_fit_recovers_a_known_pose(position, yaw_deg):
    landmarks, truth = landmarks_of(position, yaw_deg)
    head = fit_head(landmarks, face_model(), CAMERA)
    assert head is not None
    assert np.allclose(head.translation, position, atol=1e-3)
    fitted = Rotation.from_quat(head.rotation)
    assert (fitted.inv() * truth).magnitude() < math.radians(0.5)


def test_facing_is_the_services_rule_on_the_fitted_pose():
    for yaw_deg, facing in [(0.0, True), (15.0, True), (30.0, False), (-40.0, False)]:
        landmarks, _ = landmarks_of((1.2, 0.0, 0.0), yaw_deg)
        head = fit_head(landmarks, face_model(), CAMERA)
        assert head is not None
        _, angle, _, said = classify_one(head.translation, head.rotation, 20.0)
        assert said is facing and angle == pytest.approx(abs(yaw_deg), abs=0.5)


def test_a_mounted_camera_moves_the_pose_into_the_robots_frame():
    landmarks, truth = landmarks_of((1.0, 0.2, 0.0), 0.0)
    mount = Mount.of(0.1, 0.0, 1.2, 90.0, 0.0, 0.0)  # 1.2 m up, looking to the robot's left
    head = fit_head(landmarks, face_model(), CAMERA, mount)
    assert head is not None
    assert np.allclose(head.translation, (0.1 - 0.2, 1.0, 1.2), atol=1e-3)
    expected = Rotation.from_euler("Z", 90.0, degrees=True) * truth
    assert (Rotation.from_quat(head.rotation).inv() * expected).magnitude() < math.radians(0.5)


def test_mount_takes_static_transform_publishers_yaw_pitch_roll():
    mount = Mount.of(0, 0, 0, 30.0, -20.0, 10.0)
    oracle = Rotation.from_euler("ZYX", [30.0, -20.0, 10.0], degrees=True).as_matrix()
    assert np.allclose(mount.rotation, oracle)


@pytest.mark.parametrize("seed", range(20))
def test_quaternion_of_agrees_with_scipy(seed):
    rotation = Rotation.random(random_state=seed)
    ours = np.array(quaternion_of(rotation.as_matrix()))
    theirs = rotation.as_quat()
    assert ours[3] >= 0 and np.allclose(ours, theirs * np.sign(theirs[3]), atol=1e-9)
