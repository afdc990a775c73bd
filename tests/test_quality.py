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


#: Every layer is type-clean (issue 54); the pure core and the wire contract strictly so.
STRICT = ["facing_service/contract", "facing_service/core"]


@pytest.mark.parametrize(
    "args",
    [["facing_service"], ["--strict", *STRICT, "--follow-imports=silent"]],
    ids=["every-layer", "strict-core-and-contract"],
)
def test_mypy_finds_nothing(args):
    """mypy is a test dependency; libraries without type hints are taken as they are."""
    proc = subprocess.run(
        [sys.executable, "-m", "mypy", *args, "--ignore-missing-imports", "--no-error-summary"],
        cwd=ROOT, capture_output=True, text=True,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stdout + proc.stderr
