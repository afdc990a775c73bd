"""The flags every example takes, as zenoh's own examples share theirs (``common.py``):
where the service is, which base frame, for how long."""

from __future__ import annotations

import argparse
import json
from collections.abc import Callable

import zenoh


def arguments(
    doc: str, extra: Callable[[argparse.ArgumentParser], object] | None = None
) -> argparse.Namespace:
    """The parsed flags of an example whose docstring is ``doc`` (its first paragraph is
    the ``--help`` description); ``extra`` adds the example's own."""
    parser = argparse.ArgumentParser(description=" ".join(doc.split("\n\n")[0].split()))
    parser.add_argument(
        "-e", "--connect", action="append", default=[], metavar="ENDPOINT",
        help="the service's (or its router's) endpoint, e.g. tcp/127.0.0.1:7447; repeatable",
    )  # fmt: skip
    parser.add_argument("--frame", default="base_link", help="the base frame (default base_link)")
    parser.add_argument("--duration-s", type=float, help="stop after this long")
    if extra is not None:
        extra(parser)
    return parser.parse_args()


def session_config(args: argparse.Namespace) -> zenoh.Config:
    """A plain zenoh session reaching the service: the endpoints given (and then no
    multicast scouting, so that only that deployment answers), else zenoh's defaults."""
    config = zenoh.Config()
    if args.connect:
        config.insert_json5("connect/endpoints", json.dumps(args.connect))
        config.insert_json5("scouting/multicast/enabled", "false")
    return config
