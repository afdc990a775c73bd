"""The flags every example takes, as zenoh's own examples share theirs (``common.py``):
where the service is, which base frame, for how long."""

from __future__ import annotations

import argparse


def arguments(doc: str) -> argparse.Namespace:
    """The parsed flags of an example whose docstring is ``doc`` (its first paragraph is
    the ``--help`` description)."""
    parser = argparse.ArgumentParser(description=" ".join(doc.split("\n\n")[0].split()))
    parser.add_argument(
        "-e", "--connect", action="append", default=[], metavar="ENDPOINT",
        help="the service's (or its router's) endpoint, e.g. tcp/127.0.0.1:7447; repeatable",
    )  # fmt: skip
    parser.add_argument("--frame", default="base_link", help="the base frame (default base_link)")
    parser.add_argument("--duration-s", type=float, help="stop after this long")
    return parser.parse_args()
