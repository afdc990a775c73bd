"""Without the extra (the service's own install), the camera and the demo's camera are one
line with the command that installs it; the extra itself installs where it runs, or fails."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from importlib.metadata import metadata, requires

import pytest
from packaging.requirements import Requirement
from packaging.specifiers import SpecifierSet

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
        "python3 -m venv .venv-camera && .venv-camera/bin/pip install '.[camera]'\n"
    )


@pytest.mark.skipif(installed, reason="the camera extra is installed here")
def test_the_demo_asked_for_a_camera_without_the_extra_says_how_to_install_it():
    """The camera was asked for: the demo says why not and ends, rather than
    showing simulated people one line below a missed message."""
    proc = subprocess.run(
        [sys.executable, "-m", "facing_service", "demo", "--camera", "--duration-s", "2",
         "--view-port", "0"],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr == (
        "facing-service demo: --camera: the camera front end is an optional extra, not "
        "installed: python3 -m venv .venv-camera && .venv-camera/bin/pip install '.[camera]'\n"
    )
    assert "faced the robot" not in proc.stdout


def test_a_python_the_extras_wheels_do_not_exist_for_is_said(monkeypatch):
    monkeypatch.setattr(extra, "PYTHONS", ((3, 9), (3, 9)))
    here = f"{sys.version_info[0]}.{sys.version_info[1]}"
    assert extra.missing_extra() == (
        "the camera front end needs Python 3.9-3.9 (mediapipe 0.10.21 has no wheel for Python "
        f"{here}); use a venv of one of those"
    )


def test_the_pythons_said_are_those_the_package_and_the_wheels_allow():
    """A defect found: the line said 3.9-3.12 where the package requires 3.10 or later."""
    requires = SpecifierSet(metadata("facing-service")["Requires-Python"])
    low, high = extra.PYTHONS
    assert f"{low[0]}.{low[1]}" in requires and f"{low[0]}.{low[1] - 1}" not in requires
    assert high == (3, 12)


def test_the_extra_fails_to_install_where_mediapipe_has_no_wheel():
    """A defect found: on Python 3.13 ``pip install '.[camera]'`` succeeded without MediaPipe
    and said nothing (a marker left it out). Without one, pip refuses, naming it."""
    wanted = [Requirement(r) for r in requires("facing-service") or []]
    (mediapipe,) = [r for r in wanted if r.name == "mediapipe"]
    for python in ("3.10", "3.12", "3.13"):
        where = {"python_version": python, "extra": "camera"}
        assert mediapipe.marker is None or mediapipe.marker.evaluate(where), python
