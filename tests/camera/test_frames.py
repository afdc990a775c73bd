"""Frames from a folder or a video: photographs of any size become frames of one camera,
a video loops when asked and is paced at its own rate, a file that is not an image is
skipped with a line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

cv2 = pytest.importorskip(
    "cv2", reason="the camera extra is not installed: its tests run in .venv-camera (README)"
)

from facing_service.camera.frames import Source, SourceError, frames, source_of  # noqa: E402


def test_a_folders_images_of_any_size_become_frames_of_one_size(tmp_path: Path, capsys):
    cv2.imwrite(str(tmp_path / "a.png"), np.full((512, 512, 3), 200, np.uint8))
    cv2.imwrite(str(tmp_path / "b.jpg"), np.full((300, 900, 3), 50, np.uint8))
    (tmp_path / "c.png").write_bytes(b"not an image")
    (tmp_path / "notes.txt").write_text("ignored: not an image's suffix")
    images = list(frames(Source(images=tmp_path), sleep=lambda _: None))
    # the first image's own size (not 640x480, what a calibration is judged by)
    assert [image.shape for image in images] == [(512, 512, 3)] * 2
    assert capsys.readouterr().err.strip().splitlines() == [
        f"camera: skipped {tmp_path / 'c.png'}: cannot be read as an image",
        f"camera: 1 of 2 images in {tmp_path} are not 512x512: each is fitted onto a 512x512 "
        "frame (what the intrinsics describe)",
    ]
    asked = list(frames(Source(images=tmp_path, width=640, height=480), sleep=lambda _: None))
    assert [image.shape for image in asked] == [(480, 640, 3)] * 2


def test_a_video_plays_at_its_rate_and_loops_when_asked(tmp_path: Path):
    path = tmp_path / "clip.avi"
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), 10.0, (320, 240))
    for shade in range(3):
        writer.write(np.full((240, 320, 3), 60 * shade, np.uint8))
    writer.release()
    slept: list[float] = []
    played = frames(Source(video=path, loop=True), sleep=slept.append)
    shades = [int(next(played)[0, 0, 0]) for _ in range(7)]
    played.close()
    assert shades == [0, 60, 120, 0, 60, 120, 0]
    # 10 frames a second: frame k+1 is waited for until k/10 s after the start, never later
    assert len(slept) == 6 and all(0 < s <= 0.1 * (k + 1) + 1e-6 for k, s in enumerate(slept))
    assert len(list(frames(Source(video=path), sleep=lambda _: None))) == 3


def test_a_source_is_a_camera_index_a_folder_or_a_file(tmp_path: Path):
    assert source_of("2").device == 2
    assert source_of(str(tmp_path)).images == tmp_path
    (tmp_path / "clip.mp4").write_bytes(b"")
    assert source_of(str(tmp_path / "clip.mp4")).video == tmp_path / "clip.mp4"
    with pytest.raises(SourceError, match="neither a camera index nor an existing video"):
        source_of(str(tmp_path / "absent.mp4"))
    with pytest.raises(SourceError, match="no image to read"):
        frames(
            Source(images=tmp_path / "empty" if (tmp_path / "empty").mkdir() is None else tmp_path)
        )
