"""Every generated section of the docs, regenerated or checked in one command:

    python -m benchmarks.pages            # rewrite each page's measured sections
    python -m benchmarks.pages --check    # exit 1 when one differs from its results file

Each section is written from a committed results file (benchmarks/results/), never typed
in: docs/performance.md (latest.json), docs/engagement.md and docs/ros2.md
(recordings.json, engagement.json), docs/groups.md (groups.json, groups_stream.json, join.json),
docs/operations.md (churn.json), docs/camera.md (camera.json). The table in
benchmarks/README.md says which command makes each results file.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable

from . import camera_page
from .engagement import report as engagement_report
from .groups import held_out, join, stream
from .perf import churn_page, report

#: (what, how it is regenerated or checked)
PAGES: list[tuple[str, Callable[[bool], int]]] = [
    ("docs/performance.md", report.page),
    ("docs/engagement.md, docs/ros2.md", engagement_report.page),
    ("docs/groups.md: groups", held_out.page),
    ("docs/groups.md: from the stream", stream.page),
    ("docs/groups.md: where to stand", join.page),
    ("docs/operations.md: an hour of churn", churn_page.page),
    ("docs/camera.md", camera_page.page),
]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="exit 1 when a page is stale")
    args = parser.parse_args(argv)
    stale = [what for what, page in PAGES if page(args.check) != 0]
    if stale:
        print(f"stale: {'; '.join(stale)}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
