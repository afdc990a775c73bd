"""Zenoh key expressions of the wire contract: build, parse, validate.

Layout (``NS`` is the namespace, one or more chunks such as ``hri`` or ``robot1/hri``)::

    NS/bodies/<body_id>/pose/<base_frame>     input poses (PUT) and body lost (DELETE)
    NS/bodies/<body_id>/facing/<base_frame>   per-body result (PUT) and lost/stale (DELETE)
    NS/facing/<base_frame>                    per-frame aggregate
    NS/bodies/<body_id>/engagement/<frame>    per-body engagement level
    NS/events/engagement/<base_frame>         engagement level changes
    NS/groups/<base_frame>                    every F-formation of a frame (on change)
    NS/groups/<base_frame>/<group_id>         one group (PUT), dissolved (DELETE)
    NS/gazing/<base_frame>                    who faces whom in a frame (on change)
    NS/services/facing/<instance>             liveliness token while a service runs
    NS/services/facing/<instance>/status      status queryable

Names are restricted to ``[A-Za-z0-9_.-]{1,64}`` so that a name can never smuggle a key
separator or wildcard (``/ * $ # ?``) into a key.
"""

from __future__ import annotations

import re
from typing import NamedTuple

ALL_FRAMES = "*"


class BodyRef(NamedTuple):
    """Which body, in which base frame: the identity a pose, a result, a key, the
    tracker's state and the client's callbacks all carry. Both are strings, so a
    transposition would type-check: build it by keyword, ``BodyRef(frame_id=...,
    body_id=...)``, as the per-body key builders take them (keyword-only: a key reads
    ``NS/bodies/<body>/.../<frame>``, the other order). A tuple underneath, so hashing it
    costs what a pair costs."""

    frame_id: str
    body_id: str


NAME_PATTERN = r"^[A-Za-z0-9_.-]{1,64}$"
_NAME = re.compile(NAME_PATTERN)


def is_name(name: str) -> bool:
    """True when ``name`` is a valid body id or frame name."""
    return _NAME.fullmatch(name) is not None


#: How much of one name from a sender a refusal, log line or finding quotes.
NAME_QUOTED = 80


def cut(text: str, most: int = NAME_QUOTED) -> str:
    """``text`` from a sender as the service quotes it: at most ``most`` characters, and
    its full length said when cut (a 1 MB frame name made a 3 MB log line)."""
    return text if len(text) <= most else f"{text[:most]}... ({len(text)} chars)"


def validate_name(name: str, what: str = "name") -> str:
    if not is_name(name):
        raise ValueError(f"invalid {what} {name!r}: must match {NAME_PATTERN}")
    return name


def validate_namespace(namespace: str) -> str:
    """A namespace is one or more valid names joined by ``/``."""
    for chunk in namespace.split("/"):
        if not is_name(chunk):
            raise ValueError(
                f"invalid namespace {namespace!r}: each '/'-separated chunk must match "
                f"{NAME_PATTERN}"
            )
    return namespace


def validate_frame_filter(frame: str) -> str:
    """The ``--base-frame`` setting: one frame name, or ``*`` for every frame."""
    return frame if frame == ALL_FRAMES else validate_name(frame, "base frame")


def pose_key(namespace: str, *, body_id: str, frame_id: str) -> str:
    return f"{namespace}/bodies/{body_id}/pose/{frame_id}"


def facing_key(namespace: str, *, body_id: str, frame_id: str) -> str:
    return f"{namespace}/bodies/{body_id}/facing/{frame_id}"


def engagement_key(namespace: str, *, body_id: str, frame_id: str) -> str:
    return f"{namespace}/bodies/{body_id}/engagement/{frame_id}"


def event_key(namespace: str, frame_id: str) -> str:
    return f"{namespace}/events/engagement/{frame_id}"


def frame_key(namespace: str, frame_id: str) -> str:
    return f"{namespace}/facing/{frame_id}"


def groups_key(namespace: str, frame_id: str) -> str:
    return f"{namespace}/groups/{frame_id}"


def group_key(namespace: str, frame_id: str, group_id: str) -> str:
    return f"{namespace}/groups/{frame_id}/{group_id}"


def gazing_key(namespace: str, frame_id: str) -> str:
    return f"{namespace}/gazing/{frame_id}"


def service_token(namespace: str, instance: str) -> str:
    return f"{namespace}/services/facing/{instance}"


def instance_of(token_key: str) -> str:
    """``NS/services/facing/<instance>`` -> ``<instance>``."""
    return token_key.rsplit("/", 1)[-1]


def status_key(namespace: str, instance: str) -> str:
    """``instance`` may be ``*`` to ask every running service."""
    return f"{service_token(namespace, instance)}/status"


#: A key chunk no name can be (``~`` is outside the name alphabet): the worker's wake-ups.
WAKE_CHUNK = "~wake"


def wake_key(subscription: str) -> str:
    """A key ``subscription`` matches that no valid input key is: every ``*`` chunk
    becomes ``WAKE_CHUNK`` (a key without wildcards is its own, told apart by a token)."""
    return "/".join(
        WAKE_CHUNK if chunk == ALL_FRAMES else chunk for chunk in subscription.split("/")
    )


def pose_subscription(namespace: str, frame: str) -> str:
    """What the service subscribes to; ``frame`` may be ``*``."""
    return pose_key(namespace, body_id=ALL_FRAMES, frame_id=frame)


def mistyped_pose_keys(namespace: str) -> tuple[str, ...]:
    """Where a tracker's poses land when their key is mistyped: no frame chunk, chunks
    after the frame, ``body`` for ``bodies``, ``poses`` for ``pose``, the namespace left
    out. No valid pose and no output of the service matches any of them, so the service
    can subscribe to count and log them (they would otherwise vanish unseen)."""
    mistakes = (
        f"{namespace}/bodies/*/pose",
        f"{namespace}/bodies/*/pose/*/*/**",
        f"{namespace}/body/**",
        f"{namespace}/bodies/*/poses/**",
    )
    return mistakes if namespace == "bodies" else (*mistakes, "bodies/*/pose/**")


def result_queryables(namespace: str) -> tuple[str, str]:
    """The two result key spaces the service answers queries on, in every frame (one it
    does not know is answered ``unknown_frame``, even with a fixed base frame)."""
    return facing_key(namespace, body_id=ALL_FRAMES, frame_id=ALL_FRAMES), frame_key(
        namespace, ALL_FRAMES
    )


def published_spaces(namespace: str) -> tuple[str, ...]:
    """Every key space the service puts or deletes on, for any body and frame."""
    return (
        facing_key(namespace, body_id=ALL_FRAMES, frame_id=ALL_FRAMES),
        frame_key(namespace, ALL_FRAMES),
        engagement_key(namespace, body_id=ALL_FRAMES, frame_id=ALL_FRAMES),
        event_key(namespace, ALL_FRAMES),
        groups_key(namespace, ALL_FRAMES),
        group_key(namespace, ALL_FRAMES, ALL_FRAMES),
        gazing_key(namespace, ALL_FRAMES),
    )


def served_spaces(namespace: str) -> tuple[str, ...]:
    """Every key space the service answers queries on (its queryables, any frame)."""
    return (
        *result_queryables(namespace),
        engagement_key(namespace, body_id=ALL_FRAMES, frame_id=ALL_FRAMES),
        groups_key(namespace, ALL_FRAMES),
        gazing_key(namespace, ALL_FRAMES),
        status_key(namespace, ALL_FRAMES),
    )


def body_of(key: str) -> BodyRef:
    """The body of any per-body key (``.../bodies/<id>/<kind>/<frame>``) received on a
    subscription to that key space."""
    parts = key.rsplit("/", 3)
    return BodyRef(frame_id=parts[-1], body_id=parts[-3])


def parse_pose_key(namespace: str, key: str) -> BodyRef | None:
    """The body an input key is about, or None when it is not a valid one.

    The subscription already restricts the shape; this also rejects names outside the
    allowed alphabet (zenoh accepts far more than we do).
    """
    prefix = f"{namespace}/bodies/"
    if not key.startswith(prefix):
        return None
    parts = key[len(prefix) :].split("/")
    if len(parts) != 3 or parts[1] != "pose":
        return None
    body_id, _, frame_id = parts
    if not (is_name(body_id) and is_name(frame_id)):
        return None
    return BodyRef(frame_id=frame_id, body_id=body_id)


class PoseKeyParser:
    """``parse_pose_key`` remembering its answers: a tracker repeats the same few keys at
    30 Hz, and a dict lookup costs a tenth of the parse (0.1 vs 1.2 us). Bounded: the
    memory is cleared whenever it holds ``capacity`` keys, so a flood of distinct keys
    costs parses, never memory."""

    def __init__(self, namespace: str, capacity: int) -> None:
        self.namespace = namespace
        self.capacity = capacity
        self._known: dict[str, BodyRef | None] = {}

    def __call__(self, key: str) -> BodyRef | None:
        try:
            return self._known[key]
        except KeyError:
            pass
        if len(self._known) >= self.capacity:
            self._known.clear()
        parsed = self._known[key] = parse_pose_key(self.namespace, key)
        return parsed


def natural_order(name: str) -> tuple[tuple[int, int | str], ...]:
    """Sort key reading digit runs as numbers: p2 before p10 (a string sort puts p10
    first), whatever the mix of letters and digits."""
    return tuple(
        (0, int(part)) if part.isdigit() else (1, part) for part in re.findall(r"\d+|\D+", name)
    )
