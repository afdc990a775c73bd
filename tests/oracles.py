"""Independent implementations the tests compare against, and the real recordings: ROS's
own tf2 BufferCore (Debian's python3-tf2 on the system Python, through ``tf2_oracle.py``)."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

ORACLE = Path(__file__).resolve().parent / "tf2_oracle.py"
SYSTEM_PYTHON = "/usr/bin/python3"
#: The shared real recordings (../shared beside the project).
BAGS = Path(__file__).resolve().parents[2] / "shared" / "data" / "hri_engagement_bags"


def oracle(scenarios: list[list[list]]) -> list[list[dict]]:
    """The tf2 results; fails (never skips) without python3-tf2: CI installs it."""
    if (
        shutil.which(SYSTEM_PYTHON) is None
        or subprocess.run(
            [SYSTEM_PYTHON, "-c", "import tf2_py"], capture_output=True, check=False
        ).returncode
    ):
        pytest.fail("ROS's tf2 is the oracle: apt-get install python3-tf2 (see .ci/run)")
    proc = subprocess.run(
        [SYSTEM_PYTHON, str(ORACLE)],
        input=json.dumps(scenarios),
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
    )
    return json.loads(proc.stdout)
