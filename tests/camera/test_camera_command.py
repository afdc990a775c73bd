"""``facing-service camera`` and ``demo --camera`` as a user runs them: a photograph's face
reaches a real service, which decides it faces the robot; every failure is one line, the
demo's too (a camera asked for and not had ends it)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import urllib.request
from pathlib import Path

import pytest

pytest.importorskip(
    "mediapipe", reason="the camera extra is not installed: its tests run in .venv-camera (README)"
)
import cv2
import numpy as np
import skimage.data

from facing_service.testing import LOOPBACK_FLAGS, running_cli

from browser import Browser
from loopback import endpoint, free_port, wait_until

COMMAND = [sys.executable, "-m", "facing_service"]
#: Set to a path (docs/camera_view.png) to save the screenshot docs/camera.md shows.
SCREENSHOT = os.environ.get("FACING_TEST_CAMERA_SCREENSHOT")


@pytest.fixture(scope="module")
def photos(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("photos")
    cv2.imwrite(str(folder / "1.png"), cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2BGR))
    return folder


def run(*args: str, timeout: float = 60) -> subprocess.CompletedProcess[str]:
    return subprocess.run([*COMMAND, *args], capture_output=True, text=True, timeout=timeout)


@pytest.mark.slow
def test_a_photographed_face_reaches_the_service_which_says_it_faces(net, photos: Path):
    _, ep = net.service()
    recorder = net.recorder(net.client(ep), "hri/bodies/*/facing/cam")
    proc = run("camera", "--images", str(photos), "--base-frame", "cam", "-e", ep, *LOOPBACK_FLAGS)
    assert proc.returncode == 0, proc.stderr
    assert "f1 facing the camera" in proc.stdout
    assert "published 1 poses and 1 deletes, 1 heard by a subscriber" in proc.stdout
    (result,) = recorder.wait_for(lambda r: r.kind == "put", timeout=10)
    assert result.key == "hri/bodies/f1/facing/cam" and result.value["facing"] is True
    recorder.wait_for(lambda r: r.kind == "delete", timeout=10)  # the face's end said
    assert proc.stderr == ""  # MediaPipe's native start-up lines kept off the terminal


@pytest.mark.slow
def test_a_camera_publishing_to_nobody_says_so_while_it_runs(photos: Path):
    """A defect found: ``camera -e tcp/127.0.0.1:1`` printed its faces as if all were well, and
    said nobody heard only at its end (a webcam has none)."""
    nowhere = endpoint(free_port())
    args = ("camera", "--images", str(photos), "--loop", "-e", nowhere, *LOOPBACK_FLAGS)
    with running_cli(*args) as proc:
        assert proc.stdout is not None
        lines = [proc.stdout.readline()]
        while "nobody hears yet" not in lines[-1]:
            lines.append(proc.stdout.readline())
            assert lines[-1], lines
        assert proc.poll() is None  # said while it runs
    assert f"facing-service camera: nothing answers at {nowhere}" in lines[-1]


@pytest.mark.slow
def test_a_mounted_camera_says_facing_the_camera_by_the_camera(net, photos: Path):
    """A defect found: with --camera-pose, a face looking into the camera was said "not facing
    the camera (28°)": the angle was the service's, to the robot's origin."""
    _, ep = net.service()
    recorder = net.recorder(net.client(ep), "hri/bodies/*/facing/cam")
    mount = ("--camera-pose", "1", "1", "1.2", "0", "0", "0")  # 1 m ahead and 1 m left
    proc = run("camera", "--images", str(photos), "--base-frame", "cam", *mount, "-e", ep,
               *LOOPBACK_FLAGS)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    # the photograph's own 512 px frame at 65° (on a 640x480 frame it read 0.85 m)
    assert "f1 facing the camera (1°, 0.65 m)" in proc.stdout, proc.stdout
    (result,) = recorder.wait_for(lambda r: r.kind == "put", timeout=10)
    assert result.value["facing"] is False  # toward the robot's origin: 28° off
    assert result.value["angle_deg"] > 20


@pytest.mark.parametrize(
    ("args", "code", "said"),
    [
        (["--device", "57"], 1, "no camera 57: /dev/video57 does not exist"),
        (["--video", "/nonexistent/talk.mp4"], 2, "/nonexistent/talk.mp4: no such file"),
        (["--video", __file__], 1, "cannot be read as a video"),
        (["--images", "/nonexistent"], 2, "/nonexistent: no such folder"),
        (["--calibration", "/nonexistent.yaml"], 2, "--calibration: /nonexistent.yaml: No such"),
        (["--fov-deg", "190"], 2, "--fov-deg: must be from 10 to 170 degrees"),
        (["--fov-deg", "179"], 2, "--fov-deg: must be from 10 to 170 degrees"),
        (["--fov-deg", "5"], 2, "--fov-deg: must be from 10 to 170 degrees"),
        (["--camera-pose", "0", "0", "1", "nan", "0", "0"], 2, "must be a finite number"),
    ],
)
def test_each_failure_is_one_line(args: list[str], code: int, said: str):
    proc = run("camera", *args, "-e", endpoint(free_port()), *LOOPBACK_FLAGS)
    assert proc.returncode == code, proc.stderr
    assert said in proc.stderr and len(proc.stderr.strip().splitlines()) == 1, proc.stderr


@pytest.mark.slow
def test_demo_with_a_camera_shows_the_face_on_the_page_as_a_person_sees_it(photos: Path):
    """The page in a real browser: the photographed face is a person, facing, ENGAGED."""
    port = free_port()
    demo = subprocess.Popen(
        [*COMMAND, "demo", "--camera", str(photos), "--duration-s", "30", "--view-port",
         str(port)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    browser = Browser(width=1200, height=720)
    try:
        wait_until(lambda: _answers(port), 20, "the demo's page")
        browser.open(f"http://127.0.0.1:{port}/")
        browser.wait_for(
            "document.querySelector('g.person[data-id=\"f1\"]')?.dataset.level === 'ENGAGED'",
            timeout=20,
        )
        if SCREENSHOT:
            browser.screenshot(Path(SCREENSHOT))
    finally:
        browser.close()
        demo.send_signal(signal.SIGINT)
        out, err = demo.communicate(timeout=30)
    assert f"demo: the people are the faces of images in {photos}" in out, err
    assert out.strip().endswith("faced the robot during the demo: f1")


def _answers(port: int) -> bool:
    try:
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=1):
            return True
    except OSError:
        return False


@pytest.fixture(scope="module")
def video(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A 640x480 video of the astronaut, a second long."""
    path = tmp_path_factory.mktemp("video") / "faces.avi"
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), 10, (640, 480))
    frame = cv2.resize(cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2BGR), (640, 480))
    for _ in range(10):
        writer.write(frame)
    writer.release()
    return path


def test_a_calibration_of_another_aspect_is_refused_in_one_line_before_the_first_frame(
    video: Path, tmp_path: Path
):
    """A defect found: a valid camera_info for 1280x720 with a 640x480 video printed a traceback
    (camera), or a thread's traceback under the live view and nobody (demo, exit 0)."""
    calibration = tmp_path / "ci_169.yaml"
    calibration.write_text(CAMERA_INFO_1280X720)
    said = f"--calibration: {calibration}: calibrated for 1280x720, frames are 640x480"
    nowhere = ("-e", endpoint(free_port()), *LOOPBACK_FLAGS)
    for command in (
        ["camera", "--video", str(video), *nowhere],
        ["demo", "--camera", str(video), "--duration-s", "5", "--view-port", "0"],
    ):
        proc = run(*command, "--calibration", str(calibration), timeout=30)
        assert proc.returncode == 2, (command, proc.stdout, proc.stderr)
        assert said in proc.stderr and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
        assert "Traceback" not in proc.stdout + proc.stderr


#: A valid camera_info of a 1280x720 camera (16:9).
CAMERA_INFO_1280X720 = """image_width: 1280
image_height: 720
camera_matrix: {rows: 3, cols: 3, data: [1000.0, 0.0, 640.0, 0.0, 1000.0, 360.0, 0.0, 0.0, 1.0]}
distortion_model: plumb_bob
distortion_coefficients: {rows: 1, cols: 5, data: [0.0, 0.0, 0.0, 0.0, 0.0]}
"""


@pytest.mark.parametrize(
    ("args", "code", "said"),
    [
        (["--camera", "57"], 1, "demo: no camera 57: /dev/video57 does not exist"),
        (["--camera", "nope.mp4"], 2, "neither a camera index nor an existing video or folder"),
    ],
)
def test_demo_with_a_camera_it_cannot_have_says_so_and_ends(args: list[str], code: int, said: str):
    """A defect found: a typo (``demo --camera nope.mp4``) ran the simulated people, one line
    above the live view."""
    proc = run("demo", *args, "--duration-s", "2", "--view-port", "0")
    assert proc.returncode == code, proc.stderr
    assert said in proc.stderr and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    assert "faced the robot during the demo" not in proc.stdout


def _folder_of(tmp_path: Path, name: str, width: int, height: int) -> Path:
    """A folder of one photograph on a frame of ``width`` x ``height`` (as a camera of that
    size would take it)."""
    folder = tmp_path / name
    folder.mkdir()
    face = cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2BGR)
    side = min(width, height, face.shape[0])
    frame = np.full((height, width, 3), 110, np.uint8)
    top, left = (height - side) // 2, (width - side) // 2
    frame[top : top + side, left : left + side] = cv2.resize(face, (side, side))
    cv2.imwrite(str(folder / "1.png"), frame)
    return folder


#: A valid camera_info of a 640x480 camera (4:3).
CAMERA_INFO_640X480 = """image_width: 640
image_height: 480
camera_matrix: {rows: 3, cols: 3, data: [500.0, 0.0, 320.0, 0.0, 500.0, 240.0, 0.0, 0.0, 1.0]}
distortion_model: plumb_bob
distortion_coefficients: {rows: 1, cols: 5, data: [0.0, 0.0, 0.0, 0.0, 0.0]}
"""


@pytest.mark.slow
@pytest.mark.parametrize(
    ("size", "calibrated", "said"),
    [
        ((1280, 720), CAMERA_INFO_1280X720, None),  # refused before: "frames are 640x480"
        ((1280, 720), CAMERA_INFO_640X480, "calibrated for 640x480, frames are 1280x720"),
        ((450, 450), CAMERA_INFO_640X480, "calibrated for 640x480, frames are 450x450"),
    ],
)
def test_a_folders_calibration_is_judged_against_its_images(
    tmp_path: Path, size: tuple[int, int], calibrated: str, said: str | None
):
    """A defect found: a folder's images were put on 640x480 frames (--width/--height) and the
    calibration judged against those: the images' own 1280x720 calibration was refused,
    a 640x480 one taken silently for 1280x720 or 450x450 images. Both commands."""
    folder = _folder_of(tmp_path, "images", *size)
    calibration = tmp_path / "camera.yaml"
    calibration.write_text(calibrated)
    nowhere = ("-e", endpoint(free_port()), *LOOPBACK_FLAGS)
    for command in (
        ["camera", "--images", str(folder), *nowhere],
        ["demo", "--camera", str(folder), "--duration-s", "3", "--view-port", "0"],
    ):
        proc = run(*command, "--calibration", str(calibration), timeout=60)
        if said is None:
            assert "--calibration" not in proc.stderr, (command, proc.stderr)
            assert "Traceback" not in proc.stdout + proc.stderr
            assert proc.returncode == (1 if command[0] == "camera" else 0), proc.stderr
        else:
            assert proc.returncode == 2, (command, proc.stdout, proc.stderr)
            assert said in proc.stderr and len(proc.stderr.strip().splitlines()) == 1
