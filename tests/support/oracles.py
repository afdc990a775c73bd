"""Independent implementations the tests compare against, and the real recordings: ROS's
own tf2 BufferCore (Debian's python3-tf2 on the system Python, through ``tf2_oracle.py``)."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

from system_packages import require

ORACLE = Path(__file__).resolve().parent / "tf2_oracle.py"
SYSTEM_PYTHON = "/usr/bin/python3"
#: The team's shared data (../shared/data beside the project: recordings, F-formation
#: sequences). A user's clone has none: tests marked ``shared_data`` skip there, saying so,
#: and fail in the project's CI (``FACING_TEST_REQUIRE_SHARED_DATA=1``, set by .ci/run), which
#: must run every test (see conftest.py).
SHARED_DATA = Path(__file__).resolve().parents[3] / "shared" / "data"
#: The shared real recordings.
BAGS = SHARED_DATA / "hri_engagement_bags"


def shared_data_missing() -> str | None:
    """Why the tests that read ../shared/data cannot run here, or None when they can."""
    if SHARED_DATA.is_dir():
        return None
    return (
        f"needs the team's shared data at {SHARED_DATA} (recordings and F-formation "
        "sequences, not part of a clone)"
    )


#: Set by .ci/run: a test of the shared data fails without it instead of skipping. Not
#: ``CI``: GitHub Actions and GitLab set ``CI=true`` themselves, and a user's fork has no
#: ../shared.
REQUIRE_SHARED_DATA = "FACING_TEST_REQUIRE_SHARED_DATA"


def shared_data_required() -> bool:
    return os.environ.get(REQUIRE_SHARED_DATA, "") == "1"


def recording_names() -> list[str]:
    """The shared recordings' names, to parametrize over; one placeholder where there
    are none (its test is skipped, or failed in CI, before it runs)."""
    if not BAGS.is_dir():
        return ["no-shared-data"]
    return sorted(p.name for p in BAGS.iterdir() if p.is_dir())


def oracle(scenarios: list[list[list]]) -> list[list[dict]]:
    """The tf2 results (skipped without python3-tf2 on a contributor's clone, failed in
    CI, which installs it)."""
    require("python3-tf2")
    proc = subprocess.run(
        [SYSTEM_PYTHON, str(ORACLE)],
        input=json.dumps(scenarios),
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
    )
    return json.loads(proc.stdout)
