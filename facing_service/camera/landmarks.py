"""Faces and their landmarks in a frame, by MediaPipe's legacy solutions, whose models ship
inside the wheel (they run offline): the full-range face detector finds the faces, then the
face mesh places the landmarks of each, on a crop around it.

Why two stages: the face mesh alone looks for faces with the short-range detector, made for
a face filling a phone's selfie (it missed a face 150 px wide in a 640x480 frame, measured):
a robot meets people at one to four metres, where faces are 30-100 px wide. The full-range
detector is made for those (MediaPipe: up to 5 m); on a crop scaled up around each face,
the mesh then sees a face it was made for.
"""

from __future__ import annotations

import os

import cv2
import numpy as np
from numpy.typing import NDArray

from .face_ids import FaceSeen
from .frames import Image

#: MediaPipe's C++ logs its start-up at INFO and WARNING on stderr; our own lines say
#: what matters. An operator's own setting still wins.
os.environ.setdefault("GLOG_minloglevel", "2")

import mediapipe as mp

FloatArray = NDArray[np.float64]
#: The face mesh's landmarks (without the iris refinement).
LANDMARKS = 468
#: The crop around a detected face: this many times the detector's box, squared, at this
#: many pixels (the mesh's own input is 192 px, on a face its detector finds in the crop).
CROP_MARGIN = 2.0
CROP_PX = 256


class FaceMesh:
    """The landmarks of up to ``max_faces`` faces a frame, in the frame's pixels."""

    def __init__(self, max_faces: int) -> None:
        self._max_faces = max_faces
        self._detector = mp.solutions.face_detection.FaceDetection(
            model_selection=1, min_detection_confidence=0.5
        )
        self._mesh = mp.solutions.face_mesh.FaceMesh(
            static_image_mode=True, max_num_faces=1, refine_landmarks=False,
            min_detection_confidence=0.5,
        )  # fmt: skip

    def __call__(self, image: Image) -> list[FloatArray]:
        height, width = image.shape[:2]
        detections = self._detector.process(image).detections or []
        detections = sorted(detections, key=lambda d: -d.score[0])[: self._max_faces]
        found = []
        for detection in detections:
            box = detection.location_data.relative_bounding_box
            centre = np.array(
                [(box.xmin + box.width / 2) * width, (box.ymin + box.height / 2) * height]
            )
            side = CROP_MARGIN * max(box.width * width, box.height * height)
            landmarks = self._landmarks(image, centre, side)
            if landmarks is not None:
                found.append(landmarks)
        return found

    def _landmarks(self, image: Image, centre: FloatArray, side: float) -> FloatArray | None:
        """The mesh on a square crop of ``side`` pixels about ``centre`` (padded where it
        leaves the frame), its landmarks mapped back to the frame."""
        scale = CROP_PX / side
        corner = centre - side / 2.0
        warp = np.array([[scale, 0.0, -corner[0] * scale], [0.0, scale, -corner[1] * scale]])
        crop = cv2.warpAffine(image, warp, (CROP_PX, CROP_PX), flags=cv2.INTER_LINEAR)
        faces = self._mesh.process(crop).multi_face_landmarks
        if not faces:
            return None
        points = np.array([(p.x, p.y) for p in faces[0].landmark[:LANDMARKS]], dtype=np.float64)
        return points * (CROP_PX / scale) + corner

    def close(self) -> None:
        self._detector.close()
        self._mesh.close()


def seen(landmarks_px: FloatArray) -> FaceSeen:
    """A face's centre and width in the frame, for keeping its id."""
    low, high = landmarks_px.min(axis=0), landmarks_px.max(axis=0)
    centre = (low + high) / 2.0
    return FaceSeen(float(centre[0]), float(centre[1]), float(high[0] - low[0]))
