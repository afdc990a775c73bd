"""``facing-service camera`` and ``demo --camera`` as a user runs them: a photograph's face
reaches a real service, which decides it faces the robot; every failure is one line; the
demo falls back to its simulated people when the camera cannot be had."""

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
import skimage.data

from facing_service.testing import LOOPBACK_FLAGS

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


@pytest.mark.parametrize(
    ("args", "code", "said"),
    [
        (["--device", "57"], 1, "no camera 57: /dev/video57 does not exist"),
        (["--video", "/nonexistent/talk.mp4"], 1, "/nonexistent/talk.mp4: no such file"),
        (["--video", __file__], 1, "cannot be read as a video"),
        (["--images", "/nonexistent"], 1, "/nonexistent: no such folder"),
        (["--calibration", "/nonexistent.yaml"], 2, "--calibration: /nonexistent.yaml: No such"),
        (["--fov-deg", "190"], 2, "--fov-deg: must be below 180 degrees"),
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


@pytest.mark.slow
def test_demo_without_a_camera_falls_back_to_its_simulated_people():
    proc = run("demo", "--camera", "57", "--duration-s", "2", "--view-port", "0")
    assert proc.returncode == 0, proc.stderr
    assert "demo: no camera 57: /dev/video57 does not exist" in proc.stderr
    assert "demo: simulated people instead" in proc.stdout
    assert "faced the robot during the demo: p" in proc.stdout
