"""The generic 3D face fitted to a face's landmarks: MediaPipe's canonical face, in the
REP 155 face frame and in metres.

Why MediaPipe's own model: its vertices are the face mesh's landmarks one for one, in real
size (an average adult's face), so fitting them with the camera's intrinsics gives both the
head's orientation and its distance; and its 33-point basis is the set MediaPipe itself
judged rigid (no lips, no eyelids). Both files are upstream copies, pinned (model/README.md).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

MODEL = Path(__file__).with_name("model")
#: The sellion, the deepest point between the eyes: the face frame's origin (REP 155 puts
#: the face frame between the eyes).
SELLION = 168
#: Centimetres, MediaPipe's unit, to metres.
CM = 0.01


@dataclass(frozen=True)
class FaceModel:
    """``points[i]`` is landmark ``ids[i]`` in the face frame: x out of the face, y to the
    face's left, z up (REP 155), metres, origin at the sellion."""

    ids: tuple[int, ...]
    points: NDArray[np.float64]


def canonical_vertices(text: str) -> NDArray[np.float64]:
    """The ``v`` lines of a Wavefront OBJ, as an (N, 3) array in the file's own frame."""
    rows = [line.split()[1:4] for line in text.splitlines() if line.startswith("v ")]
    return np.array(rows, dtype=np.float64)


def procrustes_ids(text: str) -> tuple[int, ...]:
    """The landmark ids of a geometry pipeline's ``procrustes_landmark_basis``."""
    return tuple(int(found) for found in re.findall(r"landmark_id:\s*(\d+)", text))


def in_face_frame(canonical: NDArray[np.float64]) -> NDArray[np.float64]:
    """Canonical (x left, y up, z out; cm) to the face frame (x out, y left, z up; m),
    about the sellion. A cyclic swap of axes: still right-handed."""
    centred = (canonical - canonical[SELLION]) * CM
    return np.ascontiguousarray(centred[:, [2, 0, 1]])


@cache
def face_model() -> FaceModel:
    """The rigid landmarks of the canonical face, read once from the pinned copies."""
    vertices = in_face_frame(canonical_vertices((MODEL / "canonical_face_model.obj").read_text()))
    basis = procrustes_ids((MODEL / "geometry_pipeline_metadata_landmarks.pbtxt").read_text())
    return FaceModel(ids=basis, points=vertices[list(basis)])
