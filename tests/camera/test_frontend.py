"""The front end lets go of its capture and models however it ends (a publish
failing in ``run``'s end skipped ``close()``; a ``FaceMesh`` failing to load left the
opened video to the garbage collector)."""

from __future__ import annotations

from collections.abc import Generator
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip(
    "mediapipe", reason="the camera extra is not installed: its tests run in .venv-camera (README)"
)
import cv2
import skimage.data

from facing_service.camera import frontend
from facing_service.camera.frames import Source
from facing_service.camera.frontend import CameraFeed, CameraOptions


class Capture:
    """Frames as a source gives them, and whether the source was let go."""

    def __init__(self, image: np.ndarray, count: int) -> None:
        self.image, self.count, self.released = image, count, False

    def __call__(self, _source: Source) -> Generator[np.ndarray, None, None]:
        try:
            for _ in range(self.count):
                yield self.image
        finally:
            self.released = True


@pytest.fixture
def capture(monkeypatch: pytest.MonkeyPatch) -> Capture:
    frame = cv2.resize(skimage.data.astronaut(), (640, 480))
    source = Capture(frame, 3)
    monkeypatch.setattr(frontend, "frames", source)
    return source


def options() -> CameraOptions:
    return CameraOptions(source=Source(images=Path("unused")))


def test_a_publish_failing_at_the_end_still_releases_the_capture(capture: Capture):
    feed = CameraFeed(options())

    def publish(key: str, payload: bytes | None) -> None:
        if payload is None:  # the session closed under the front end
            raise RuntimeError("session closed")

    with pytest.raises(RuntimeError, match="session closed"):
        feed.run(publish, say=lambda line: None)
    assert capture.released and feed._frames is None


def test_models_failing_to_load_release_the_opened_capture(
    capture: Capture, monkeypatch: pytest.MonkeyPatch
):
    def broken(_max_faces: int, _tile_px: int | None) -> None:
        raise RuntimeError("no graph")

    monkeypatch.setattr(frontend, "FaceMesh", broken)
    with pytest.raises(RuntimeError, match="no graph"):
        CameraFeed(options())
    assert capture.released


def test_the_first_frame_read_to_check_the_calibration_is_not_lost(capture: Capture):
    seen: list[str] = []
    feed = CameraFeed(options())
    stats = feed.run(lambda key, payload: seen.append(key), say=lambda line: None)
    assert stats.frames == 3 and stats.faces_seen == 1


def test_the_facing_lines_keep_the_services_hysteresis():
    """A defect found: a face at the threshold flickered "facing (19°)", "not facing (20°)",
    "facing (20°)" where the service, with its 5° of hysteresis, said facing throughout."""
    from facing_service.camera.head_pose import HeadPose
    from facing_service.contract.poses import yaw_rotation

    said: list[str] = []
    lines = frontend._FacingLines(20.0, 5.0, said.append)
    for t, off in enumerate([19.0, 20.5, 19.5, 24.0, 26.0, 22.0, 19.0]):
        # 1 m in front of the camera, looking back at it turned ``off`` degrees
        lines.said("f1", HeadPose((1.0, 0.0, 0.0), yaw_rotation(180.0 + off)), float(t))
    verdicts = [line.split("f1 ")[1].split(" (")[0] for line in said]
    assert verdicts == ["facing the camera", "not facing the camera", "facing the camera"]
    assert [round(float(line.split("(")[1].split("°")[0])) for line in said] == [19, 26, 19]
