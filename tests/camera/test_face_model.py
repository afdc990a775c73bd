"""The generic face is MediaPipe's own, unchanged, and turned into the REP 155 face frame
the right way round (a wrong axis would make every face look away)."""

from __future__ import annotations

import hashlib

import numpy as np

from facing_service.camera.face_model import MODEL, SELLION, face_model, in_face_frame

#: Git blob ids at google-ai-edge/mediapipe v0.10.21 (cad7f3ab), read from the upstream
#: repository: ``git rev-parse v0.10.21:mediapipe/modules/face_geometry/data/<file>``.
UPSTREAM_BLOBS = {
    "canonical_face_model.obj": "0e666d1c4e75949d1639c2bcf347a38da4834164",
    "geometry_pipeline_metadata_landmarks.pbtxt": "8dfb46394f1faf109a6505dcfdbbb39d77549b57",
}
NOSE_TIP, CHIN, LEFT_EYE_OUTER, RIGHT_EYE_OUTER = 1, 152, 263, 33


def git_blob_id(data: bytes) -> str:
    return hashlib.sha1(b"blob %d\0" % len(data) + data).hexdigest()


def test_the_carried_files_are_upstreams_at_the_pinned_tag():
    for name, blob in UPSTREAM_BLOBS.items():
        assert git_blob_id((MODEL / name).read_bytes()) == blob, name


def test_the_face_frame_is_x_out_of_the_face_y_to_its_left_z_up():
    from facing_service.camera.face_model import canonical_vertices

    vertices = in_face_frame(canonical_vertices((MODEL / "canonical_face_model.obj").read_text()))
    assert np.allclose(vertices[SELLION], 0.0)
    assert vertices[NOSE_TIP, 0] > 0.01  # the nose sticks out along x
    assert vertices[LEFT_EYE_OUTER, 1] > 0.03 > -0.03 > vertices[RIGHT_EYE_OUTER, 1]
    assert vertices[CHIN, 2] < -0.08  # the chin below the eyes
    # a real face's size: outer eye corners about 9 cm apart
    assert 0.08 < vertices[LEFT_EYE_OUTER, 1] - vertices[RIGHT_EYE_OUTER, 1] < 0.10


def test_the_fit_uses_mediapipes_33_rigid_landmarks():
    model = face_model()
    assert len(model.ids) == 33 and model.points.shape == (33, 3)
    assert {4, 6, 33, 263} <= set(model.ids)  # nose, bridge, outer eye corners
    assert not {13, 14, 61, 291} & set(model.ids)  # no lips: they move when one speaks
