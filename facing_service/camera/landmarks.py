"""Faces and their landmarks in a frame, by MediaPipe's legacy solutions, whose models ship
inside the wheel (they run offline): the full-range face detector finds the faces, then the
face mesh places the landmarks of each, on a crop around it.

Why two stages: the face mesh alone looks for faces with the short-range detector, made for
a face filling a phone's selfie (it missed a face 150 px wide in a 640x480 frame, measured):
a robot meets people at one to four metres, where faces are 30-100 px wide. The full-range
detector is made for those (MediaPipe: up to 5 m); on a crop scaled up around each face,
the mesh then sees a face it was made for.

Why regions of the frame: the detector sees a 192x192 copy of what it is given,
so on a whole 1280x720 frame a face 75 px wide (2 m with a 65° camera) is 11 px to it and
found one time in seven; on a tile of 384 px a face 30 px wide (5 m) is 15 px, and found
(measured: ``python -m benchmarks.camera``). So each frame the detector looks at the whole
frame (the faces near), at ``tiles_per_frame`` tiles of the full-resolution frame in turn
(``tile_px`` wide, overlapping by a quarter, so every face narrower than a quarter tile lies
whole in one: far faces are found within a round of the tiles), and a face found is
followed on a crop around where it was (the mesh's own detector finds it there: no tile
has to find it again).
"""

from __future__ import annotations

import os
from dataclasses import dataclass

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
#: The crop around a face: this many times its width, squared, at this many pixels (the
#: mesh's own input is 192 px, on a face its detector finds in the crop).
CROP_MARGIN = 2.0
CROP_PX = 256
#: The size of the detector's own input: a region smaller than this gains nothing.
DETECTOR_PX = 192
#: Faces as narrow as this in the detector's input are found (a 30 px face on a 384 px
#: tile: 7 of 7 placements found, score 0.85 and up; measured on the astronaut's photo).
DETECTOR_FACE_PX = 15.0
#: Tiles looked at a frame: a round of 15 (1280x720, 5 m) in 8 frames, for two detector
#: runs a frame (about 10 ms of one core).
TILES_PER_FRAME = 2


@dataclass(frozen=True, slots=True)
class Box:
    """A face's square region in the frame's pixels: its centre and its width."""

    x: float
    y: float
    width: float

    def near(self, other: Box) -> bool:
        """The same face: centres closer than half the wider's width."""
        return np.hypot(self.x - other.x, self.y - other.y) < 0.5 * max(self.width, other.width)


def tiles(width: int, height: int, side: int) -> list[tuple[int, int, int]]:
    """Square tiles of ``side`` px over a frame (x, y of the corner, side), overlapping by a
    quarter, the last of each row and column flush with the frame's edge; none when one
    tile would hold the whole frame (the whole-frame look covers it)."""
    if side >= max(width, height):
        return []
    side = min(side, width, height)
    stride = max(1, side * 3 // 4)

    def starts(length: int) -> list[int]:
        found = list(range(0, max(length - side, 0) + 1, stride))
        if found[-1] != length - side:
            found.append(length - side)
        return found

    return [(x, y, side) for y in starts(height) for x in starts(width)]


class FaceMesh:
    """The landmarks of up to ``max_faces`` faces a frame, in the frame's pixels: the whole
    frame, ``tiles_per_frame`` tiles of ``tile_px`` (None: none) and the faces of the last
    frame looked at each frame."""

    def __init__(
        self, max_faces: int, tile_px: int | None = None, tiles_per_frame: int = TILES_PER_FRAME
    ) -> None:
        self._max_faces = max_faces
        self._tile_px = None if tile_px is None else max(int(tile_px), DETECTOR_PX)
        self._tiles_per_frame = tiles_per_frame
        self._next_tile = 0
        self._followed: list[Box] = []  # the faces of the last frame
        self._detector = mp.solutions.face_detection.FaceDetection(
            model_selection=1, min_detection_confidence=0.5
        )
        self._mesh = mp.solutions.face_mesh.FaceMesh(
            static_image_mode=True, max_num_faces=1, refine_landmarks=False,
            min_detection_confidence=0.5,
        )  # fmt: skip

    def __call__(self, image: Image) -> list[FloatArray]:
        found: list[FloatArray] = []
        boxes: list[Box] = []
        for box in [*self._followed, *self._detected(image)]:
            if len(found) == self._max_faces or any(box.near(b) for b in boxes):
                continue
            landmarks = self._landmarks(image, box)
            if landmarks is not None:
                found.append(landmarks)
                boxes.append(_box_of(landmarks))
        self._followed = boxes
        return found

    def _detected(self, image: Image) -> list[Box]:
        """The faces the detector finds in the whole frame and in this frame's tiles, the
        surest first."""
        height, width = image.shape[:2]
        regions = [(0, 0, width, height)]
        if self._tile_px is not None and (every := tiles(width, height, self._tile_px)):
            for k in range(min(self._tiles_per_frame, len(every))):
                x, y, side = every[(self._next_tile + k) % len(every)]
                regions.append((x, y, side, side))
            self._next_tile = (self._next_tile + self._tiles_per_frame) % len(every)
        scored: list[tuple[float, Box]] = []
        for x, y, w, h in regions:
            region = image if (w, h) == (width, height) else image[y : y + h, x : x + w]
            for detection in self._detector.process(np.ascontiguousarray(region)).detections or []:
                b = detection.location_data.relative_bounding_box
                box = Box(x + (b.xmin + b.width / 2) * w, y + (b.ymin + b.height / 2) * h,
                          max(b.width * w, b.height * h))  # fmt: skip
                scored.append((detection.score[0], box))
        return [box for _, box in sorted(scored, key=lambda sb: -sb[0])]

    def _landmarks(self, image: Image, box: Box) -> FloatArray | None:
        """The mesh on a square crop ``CROP_MARGIN`` times the face's width about its
        centre (padded where it leaves the frame), its landmarks mapped back to the frame."""
        side = CROP_MARGIN * box.width
        scale = CROP_PX / side
        corner = np.array([box.x, box.y]) - side / 2.0
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


def _box_of(landmarks_px: FloatArray) -> Box:
    """Where a face is, from its landmarks: to look for it there in the next frame."""
    face = seen(landmarks_px)
    return Box(face.x, face.y, face.width)


def seen(landmarks_px: FloatArray) -> FaceSeen:
    """A face's centre and width in the frame, for keeping its id."""
    low, high = landmarks_px.min(axis=0), landmarks_px.max(axis=0)
    centre = (low + high) / 2.0
    return FaceSeen(float(centre[0]), float(centre[1]), float(high[0] - low[0]))
