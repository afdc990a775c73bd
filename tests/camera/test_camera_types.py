"""The camera front end is type-checked against the real OpenCV and MediaPipe it runs with
(the service's own mypy run, without the extra, takes them as untyped)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip(
    "cv2", reason="the camera extra is not installed: its tests run in .venv-camera (README)"
)

ROOT = Path(__file__).resolve().parents[2]


def test_mypy_finds_nothing_with_the_extras_own_types():
    proc = subprocess.run(
        [sys.executable, "-m", "mypy", "facing_service/camera", "--ignore-missing-imports",
         "--no-error-summary"],
        cwd=ROOT, capture_output=True, text=True,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stdout + proc.stderr
