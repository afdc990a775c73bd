"""Lint and formatting are part of the test run, so CI enforces them."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize("args", [["check"], ["format", "--check"]], ids=["lint", "format"])
def test_ruff(args):
    """ruff is a test dependency; run it from this interpreter's environment."""
    proc = subprocess.run(
        [sys.executable, "-m", "ruff", *args, "."], cwd=ROOT, capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr


#: The layers kept type-clean (issue 43): the pure core, the contract, the ROS 2 codec and
#: the service's shell.
TYPED = [f"facing_service/{layer}" for layer in ("contract", "core", "ros2", "shell")]


def test_mypy_finds_nothing_in_the_typed_layers():
    """mypy is a test dependency; imports outside the typed layers are followed silently
    (checked where they are used, not reported for themselves)."""
    proc = subprocess.run(
        [sys.executable, "-m", "mypy", *TYPED, "--ignore-missing-imports",
         "--follow-imports=silent", "--no-error-summary"],
        cwd=ROOT, capture_output=True, text=True,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stdout + proc.stderr
