"""A face's head pose from its landmarks: the generic face fitted with the camera's
intrinsics (OpenCV's SQPnP), then put in the camera's body frame and, when the camera is
mounted on a robot, in the robot's base frame. Pure arithmetic on arrays (OpenCV solves).

Frames: OpenCV's camera is optical (x right, y down, z forward); ROS's ``camera_link`` and
a robot's base are x forward, y left, z up (REP 103); the face frame is REP 155's (x out of
the face, y to its left, z up), so the service reads it as it reads any body's pose.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import cv2
import numpy as np
from numpy.typing import NDArray

from ..core.tf.geometry import add, qmul, rotate
from .face_model import FaceModel
from .intrinsics import Intrinsics

FloatArray = NDArray[np.float64]

#: Optical to body frame: x_body = z_opt, y_body = -x_opt, z_body = -y_opt.
OPTICAL_TO_BODY = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])


@dataclass(frozen=True)
class Mount:
    """Where the camera sits in the robot's base frame (``camera_link`` in ``base``)."""

    translation: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rotation: FloatArray = field(default_factory=lambda: np.eye(3))

    @classmethod
    def of(
        cls, x: float, y: float, z: float, yaw_deg: float, pitch_deg: float, roll_deg: float
    ) -> Mount:
        """As ``static_transform_publisher`` takes it: x y z yaw pitch roll (rotations about
        z, then the new y, then the new x)."""
        cz, sz = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
        cy, sy = math.cos(math.radians(pitch_deg)), math.sin(math.radians(pitch_deg))
        cx, sx = math.cos(math.radians(roll_deg)), math.sin(math.radians(roll_deg))
        yaw = np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]])
        pitch = np.array([[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]])
        roll = np.array([[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]])
        return cls((x, y, z), yaw @ pitch @ roll)


@dataclass(frozen=True)
class HeadPose:
    """The face frame in ``camera_link`` or, placed (``placed``), in the base frame the
    camera is mounted in: translation (metres) and unit quaternion (x, y, z, w)."""

    translation: tuple[float, float, float]
    rotation: tuple[float, float, float, float]


def fit_head(
    landmarks_px: FloatArray, model: FaceModel, camera: Intrinsics, mount: Mount | None = None
) -> HeadPose | None:
    """The head pose of one face, from its (468, 2) landmarks in pixels; None when the fit
    fails or puts the face behind the camera."""
    image_points = np.ascontiguousarray(landmarks_px[list(model.ids)], dtype=np.float64)
    matrix = np.array([[camera.fx, 0.0, camera.cx], [0.0, camera.fy, camera.cy], [0, 0, 1.0]])
    distortion = np.array(camera.distortion, dtype=np.float64)  # empty: none
    ok, rvec, tvec = cv2.solvePnP(
        model.points, image_points, matrix, distortion, flags=cv2.SOLVEPNP_SQPNP
    )
    if not ok or tvec[2, 0] <= 0.0:
        return None
    face_in_optical, _ = cv2.Rodrigues(rvec)
    x, y, z = (float(v) for v in OPTICAL_TO_BODY @ tvec[:, 0])
    head = HeadPose((x, y, z), quaternion_of(OPTICAL_TO_BODY @ face_in_optical))
    return head if mount is None else placed(head, mount)


def placed(head: HeadPose, mount: Mount) -> HeadPose:
    """A face seen from the camera (in ``camera_link``), put where the camera is mounted."""
    turn = quaternion_of(mount.rotation)
    return HeadPose(
        add(rotate(turn, head.translation), mount.translation), qmul(turn, head.rotation)
    )


def quaternion_of(rotation: FloatArray) -> tuple[float, float, float, float]:
    """The unit quaternion (x, y, z, w) of a rotation matrix, w ≥ 0 (Shepperd's method:
    the largest of the four diagonal sums, so no division by a small number)."""
    m = rotation
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    if trace > 0:
        s = 2.0 * math.sqrt(1.0 + trace)
        q = ((m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, s / 4)
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = (s / 4, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s, (m[2, 1] - m[1, 2]) / s)
    elif m[1, 1] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        q = ((m[0, 1] + m[1, 0]) / s, s / 4, (m[1, 2] + m[2, 1]) / s, (m[0, 2] - m[2, 0]) / s)
    else:
        s = 2.0 * math.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        q = ((m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, s / 4, (m[1, 0] - m[0, 1]) / s)
    sign = -1.0 if q[3] < 0 else 1.0
    norm = math.sqrt(sum(v * v for v in q))
    x, y, z, w = (float(sign * v / norm) for v in q)
    return (x, y, z, w)
