"""``facing-service inspect``: what a robot puts on zenoh, seen as the service would read it,
the way ``ros2 topic list -v`` and ``view_frames`` show it: topics in every format, domain
and namespace, with their rate and rmw_zenoh form; the TF tree with its roots; the tracked
ids; and the flags that read it all.

``Survey`` is pure (samples in, lines out); ``inspect_robot`` is the thin shell that
listens for a few seconds.

Anything on the bus may be a stranger, so what it keeps and prints is bounded whatever is
sent: at most ``KEYS_KEPT`` keys and ``FRAMES_KEPT`` frames (the rest counted), names cut
(``keys.cut``), the tree walked without recursion and drawn in at most ``TREE_LINES``
lines, and where /tf is in more than one place every place is named, none picked.
"""

from __future__ import annotations

import sys
import threading
import time
from collections import defaultdict
from dataclasses import dataclass, field

import zenoh
import zenoh.ext

from ..config.disclosure import public_endpoint, public_endpoints, zenoh_failure
from ..config.session import zenoh_config
from ..config.settings import Settings
from ..contract.keys import cut
from ..ros2 import types as ros2_types
from ..ros2.input import publication_cache_selector
from ..ros2.people import MAX_FRAME_NAME
from ..ros2.wire import (
    HASH_NOT_SUPPORTED,
    Attachment,
    RosFormat,
    Where,
    Wire,
    attachment_layout,
    where,
)
from ..shell.ros_bus import query_publication_caches

#: The topics surveyed (without their leading slash), and their types.
TOPICS = {
    "tf": ros2_types.TF_MESSAGE,
    "tf_static": ros2_types.TF_MESSAGE,
    "humans/bodies/tracked": ros2_types.IDS_LIST,
    "humans/faces/tracked": ros2_types.IDS_LIST,
    "humans/persons/tracked": ros2_types.IDS_LIST,
}
TRANSIENT_LOCAL = ("tf_static", "humans/persons/tracked")
#: Bounds of what is kept and printed.
KEYS_KEPT = 64
FRAMES_KEPT = 10_000
TREE_LINES = 200
IDS_SHOWN = 20
PLACES_SHOWN = 5


@dataclass
class _Seen:
    where: Where
    count: int = 0
    first: float = 0.0
    last: float = 0.0
    layouts: set[Attachment | None] = field(default_factory=set)


@dataclass
class _Link:
    parent: str
    static: bool
    count: int = 0
    newest_ns: int = 0


class Survey:
    """What was seen, by key; the TF links by child; the latest tracked ids by list."""

    def __init__(self) -> None:
        self.keys: dict[str, _Seen] = {}
        self.links: dict[str, _Link] = {}
        self.tracked: dict[str, list[str]] = {}
        self.undecodable: dict[str, str] = {}
        self.tokens: list[str] = []
        self.keys_over: dict[str, int] = {}  # topic -> keys not kept (over KEYS_KEPT)
        self.frames_over = 0  # transforms of frames not kept (over FRAMES_KEPT, or too long)

    def on_sample(self, key: str, payload: bytes, extra: bytes | None, now: float) -> None:
        seen = self.keys.get(key)
        if seen is None:
            place = where(key, TOPICS)
            if place is None:
                return
            if len(self.keys) >= KEYS_KEPT:
                self.keys_over[place.topic] = self.keys_over.get(place.topic, 0) + 1
                return
            seen = self.keys[key] = _Seen(place, first=now)
        seen.count += 1
        seen.last = now
        seen.layouts.add(attachment_layout(extra))
        typename = TOPICS[seen.where.topic[1:]]
        try:
            message = ros2_types.deserialize(payload, typename)
        except Exception as error:  # another type on the topic, or bad CDR
            self.undecodable[key] = f"{type(error).__name__}: {error}"[:120]
            return
        if typename == ros2_types.IDS_LIST:
            self.tracked[key] = [cut(i, 40) for i in message.ids[:IDS_SHOWN]] + (
                [f"and {len(message.ids) - IDS_SHOWN} more"] if len(message.ids) > IDS_SHOWN else []
            )
            return
        static = seen.where.topic == "/tf_static"
        for t in message.transforms:
            child, parent = t.child_frame_id, t.header.frame_id
            long = max(len(child), len(parent)) > MAX_FRAME_NAME
            if long or (child not in self.links and len(self.links) >= FRAMES_KEPT):
                self.frames_over += 1
                continue
            link = self.links.setdefault(child, _Link(parent, static))
            link.parent, link.count = t.header.frame_id, link.count + 1
            stamp = t.header.stamp.sec * 1_000_000_000 + t.header.stamp.nanosec
            link.newest_ns = max(link.newest_ns, stamp)

    def report(self, base_frame: str, seconds: float, session: str = "") -> list[str]:
        """The report; ``session``: the session flags inspect was given, carried into the
        command it suggests (without them it would not join the same router)."""
        sections = [
            self._topics(seconds),
            self._tree(seconds),
            self._tracked(),
            self._verdict(base_frame, session),
        ]
        lines = [f"ROS 2 data seen in {seconds:g} s:"]
        for section in sections:
            lines += ["", *section]
        return lines

    def _topics(self, seconds: float) -> list[str]:
        if not self.keys:
            return [
                "topics: none of /tf, /tf_static, /humans/*/tracked in any format, domain "
                "or namespace (is this the robot's router? is anything publishing?)"
            ]
        lines = ["topics (ros2 topic list -v):"]
        for key, seen in sorted(self.keys.items(), key=lambda kv: kv[1].where.topic):
            rate = (seen.count - 1) / (seen.last - seen.first) if seen.last > seen.first else 0
            said = f"{rate:.1f} Hz" if rate else f"{seen.count} message(s)"
            layouts = {x.value for x in seen.layouts if x is not None}
            extra = f", attachments {'/'.join(sorted(layouts))}" if layouts else ""
            lines.append(f"  {seen.where.topic:24} {said:>14}  {cut(seen.where.describe())}{extra}")
            lines.append(f"  {'':24} {'':>14}  key {cut(key, 160)}")
        for topic, more in sorted(self.keys_over.items()):
            lines.append(f"  {topic}: on {more} more key(s), not listed (over {KEYS_KEPT} keys)")
        for key, why in self.undecodable.items():
            lines.append(f"  not decodable as its topic's type: {cut(key)}: {why}")
        if self.tokens:
            lines.append(
                f"  rmw_zenoh graph: {len(self.tokens)} publisher token(s) on these topics"
            )
        return lines

    def _children(self) -> dict[str, list[str]]:
        children: dict[str, list[str]] = defaultdict(list)
        for child, link in self.links.items():
            children[link.parent].append(child)
        return children

    def roots(self) -> list[str]:
        return sorted({link.parent for link in self.links.values()} - self.links.keys())

    def _tree(self, seconds: float) -> list[str]:
        if not self.links:
            return ["TF tree: no transform seen"]
        roots = self.roots()
        lines = [f"TF tree (view_frames), {len(roots)} root(s), {len(self.links)} frame(s):"]
        if self.frames_over:
            lines.append(
                f"  ({self.frames_over} transform(s) of frames not kept: names over "
                f"{MAX_FRAME_NAME} characters, or more than {FRAMES_KEPT} frames)"
            )
        children = self._children()
        drawn = 0
        # Depth first without recursion: a 1 500-link chain is a 1 500-deep walk.
        stack: list[tuple[str, int]] = [(root, 0) for root in reversed(roots)]
        seen = set(roots)
        while stack:
            frame, depth = stack.pop()
            if drawn >= TREE_LINES:
                lines.append(f"  ... and {len(self.links) + len(roots) - drawn} more frame(s)")
                break
            drawn += 1
            indent = "  " * min(depth, 20) + ("" if depth <= 20 else f"[depth {depth}] ")
            if depth == 0:
                lines.append(f"  {cut(frame)}  (root)")
            else:
                link = self.links[frame]
                how = "static" if link.static else f"{link.count / seconds:.1f} Hz"
                newest = f", newest stamp {link.newest_ns / 1e9:.3f} s" if not link.static else ""
                lines.append(f"  {indent}{cut(frame)}  ({how}{newest})")
            for child in sorted(children.get(frame, []), reverse=True):
                if child in seen:  # a loop: said once
                    lines.append(f"  {indent}  {cut(child)} (loop)")
                    continue
                seen.add(child)
                stack.append((child, depth + 1))
        return lines

    def _tracked(self) -> list[str]:
        if not self.tracked:
            return ["tracked ids: no /humans/*/tracked list seen"]
        lines = ["tracked ids (the latest list of each):"]
        for key, ids in sorted(self.tracked.items()):
            lines.append(f"  {self.keys[key].where.topic}: {', '.join(ids) or '(empty)'}")
        lines += [
            f"  ... and {n} more key(s) of {t}" for t, n in self.keys_over.items() if "tracked" in t
        ]
        return lines

    def root_of(self, frame: str) -> str:
        chain, last = {frame}, frame
        while (link := self.links.get(last)) is not None and link.parent not in chain:
            chain.add(link.parent)
            last = link.parent
        return last

    def _verdict(self, base_frame: str, session: str = "") -> list[str]:
        places = list(dict.fromkeys(s.where for s in self.keys.values() if s.where.topic == "/tf"))
        if not places:
            return ["for the service: no /tf anywhere, so no person can be placed"]
        frames = set(self.links) | {link.parent for link in self.links.values()}
        people = sorted(f for f in self.links if f.startswith(("body_", "face_")))
        lines = ["for the service (--input ros2):"]
        base = base_frame
        if base_frame not in frames:
            roots = sorted({self.root_of(p) for p in people}) or self.roots()
            base = roots[0]
            lines.append(
                f"  base frame '{cut(base_frame)}' is not in the TF tree; the people's frames "
                f"are under {', '.join(repr(cut(r)) for r in roots[:PLACES_SHOWN])}"
                + (f" and {len(roots) - PLACES_SHOWN} more" if len(roots) > PLACES_SHOWN else "")
                + " (any frame of that tree will do)"
            )
        else:
            apart = [p for p in people if self.root_of(p) != self.root_of(base_frame)]
            if apart:
                lines.append(
                    f"  {', '.join(cut(a) for a in apart[:6])} never connect to "
                    f"'{cut(base_frame)}' (another tree)"
                )
        for place in places[:1]:
            if place.distro is None and place.format == "rmw_zenoh":
                lines.append(f"  /tf's type hash is neither RIHS01 nor {HASH_NOT_SUPPORTED}")
        command = "facing-service run --input ros2" + (f" {session}" if session else "")
        if len(places) == 1:
            lines.append(f"  {command} {places[0].flags()} --base-frame {cut(base)}")
            return lines
        more = len(places) + self.keys_over.get("/tf", 0)
        lines.append(
            f"  /tf is published in {more} places (formats, domains, namespaces or forms): "
            "which one is the robot's is yours to say; the flags for each:"
        )
        for place in places[:PLACES_SHOWN]:
            lines.append(f"  {command} {place.flags()} --base-frame {cut(base)}")
        if more > PLACES_SHOWN:
            lines.append(f"  ... and {more - PLACES_SHOWN} more places")
        return lines


def session_flags(settings: Settings) -> str:
    """The session flags of the service ``inspect`` suggests, as a command line says them
    (secrets left out: endpoints as public_endpoint shows them): the ones it was given,
    and, where it was pointed at a router without saying more, the README's isolated way
    to join it (a client without multicast scouting): a plain peer would find, and be
    found by, every zenoh deployment around."""
    said = []
    unsaid = settings.config is None and settings.mode is None and bool(settings.connect)
    if settings.mode is not None:
        said.append(f"-m {settings.mode}")
    elif unsaid:
        said.append("-m client")
    said += [f"-e {public_endpoint(e)}" for e in settings.connect]
    said += [f"-l {public_endpoint(e)}" for e in settings.listen]
    if settings.config is not None:
        said.append(f"-c {settings.config}")
    if settings.no_multicast_scouting or unsaid:
        said.append("--no-multicast-scouting")
    return " ".join(said)


def inspect_robot(settings: Settings, seconds: float, base_frame: str) -> int:
    """Listen ``seconds`` for the surveyed topics in every form, then print the report."""
    survey = Survey()
    lock = threading.Lock()

    def on_sample(sample: zenoh.Sample) -> None:
        extra = sample.attachment
        with lock:
            survey.on_sample(
                str(sample.key_expr),
                sample.payload.to_bytes(),
                None if extra is None else extra.to_bytes(),
                time.monotonic(),
            )

    links = public_endpoints(settings.connect) or "zenoh's scouting"
    print(f"listening {seconds:g} s for a robot's ROS 2 topics through {links}...", flush=True)
    entities: list[zenoh.Subscriber[None] | zenoh.ext.AdvancedSubscriber[None]] = []
    try:
        with zenoh.open(zenoh_config(settings)) as session:
            try:
                for topic, typename in TOPICS.items():
                    dds = ros2_types.dds_type_name(typename)
                    for key in (f"**/{topic}", f"**/{topic}/{dds}/*"):
                        if topic in TRANSIENT_LOCAL:  # the caches of both generations
                            history = zenoh.ext.HistoryConfig(detect_late_publishers=True)
                            entities.append(
                                zenoh.ext.declare_advanced_subscriber(
                                    session, key, on_sample, history=history
                                )
                            )
                            older = [publication_cache_selector(Wire(f), key) for f in RosFormat]
                            query_publication_caches(session, older, on_sample)
                        else:
                            entities.append(session.declare_subscriber(key, on_sample))
                time.sleep(seconds)
                tokens = session.liveliness().get("@ros2_lv/**", timeout=1.0)
                with lock:
                    survey.tokens = [
                        str(r.ok.key_expr)
                        for r in tokens
                        if r.ok is not None
                        and "/MP/" in str(r.ok.key_expr)
                        and any(dds in str(r.ok.key_expr) for dds in ("TFMessage_", "IdsList_"))
                    ]
            finally:
                for entity in entities:
                    entity.undeclare()
    except zenoh.ZError as error:
        print(zenoh_failure("inspect", error), file=sys.stderr)
        return 1
    with lock:
        print("\n".join(survey.report(base_frame, seconds, session_flags(settings))))
    return 0
