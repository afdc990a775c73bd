"""Without the extra (the service's own install), the camera is one line with the command
that installs it, and the demo says so and shows its simulated people."""

from __future__ import annotations

import importlib.util
import subprocess
import sys

import pytest

from facing_service.camera import extra
from facing_service.testing import LOOPBACK_FLAGS

from loopback import endpoint, free_port

installed = importlib.util.find_spec("mediapipe") is not None


@pytest.mark.skipif(installed, reason="the camera extra is installed here")
def test_the_camera_without_its_extra_says_how_to_install_it():
    proc = subprocess.run(
        [sys.executable, "-m", "facing_service", "camera", "-e", endpoint(free_port()),
         *LOOPBACK_FLAGS],
        capture_output=True, text=True, timeout=30,
    )  # fmt: skip
    assert proc.returncode == 2
    assert proc.stderr == (
        "facing-service camera: the camera front end is an optional extra, not installed: "
        "pip install 'facing-service[camera]'\n"
    )


@pytest.mark.slow
@pytest.mark.skipif(installed, reason="the camera extra is installed here")
def test_the_demo_without_the_extra_falls_back_to_simulated_people():
    proc = subprocess.run(
        [sys.executable, "-m", "facing_service", "demo", "--camera", "--duration-s", "2",
         "--view-port", "0"],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "demo: the camera front end is an optional extra, not installed: pip install " in (
        proc.stdout
    )
    assert "faced the robot during the demo: p" in proc.stdout


def test_a_python_the_extras_wheels_do_not_exist_for_is_said(monkeypatch):
    monkeypatch.setattr(extra, "PYTHONS", ((3, 9), (3, 9)))
    here = f"{sys.version_info[0]}.{sys.version_info[1]}"
    assert extra.missing_extra() == (
        "the camera front end needs Python 3.9-3.9 (mediapipe 0.10.21 has no wheel for Python "
        f"{here}); use a venv of one of those"
    )
