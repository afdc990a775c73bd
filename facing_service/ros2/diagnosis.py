"""Why a ROS 2 robot's people give no results, said as a robot developer would find it by
hand (``ros2 topic list``, ``view_frames``): pure checks over what the service already
sees, each finding a stable code and one line to act on.

The shell runs ``findings`` every second or so, logs each finding once when it appears and
once when it clears, and shows the current ones in the status (``ros2.findings``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..contract.keys import cut
from ..core.tf.errors import TfError
from .input import TOPICS
from .people import People
from .wire import HASH_NOT_SUPPORTED, RosFormat, Wire, where

#: Seconds of nothing (or of a tree without the base frame) before a finding is said: a
#: robot's /tf streams at 10-100 Hz and its lists at the tracker's rate.
GRACE_S = 2.0
#: A "time went back" finding is shown this long after the buffer was cleared.
TIME_BACK_SHOWN_S = 10.0
#: At most this many frames or ids are named in one line.
NAMED = 6
#: Keys of ROS data seen elsewhere, remembered (the first ones: enough to say where).
STRAYS_KEPT = 8
#: Publishers remembered per read topic (GIDs seen, and nodes from liveliness tokens); the
#: rest are counted, not named: every name a sender chooses costs memory.
PUBLISHERS_KEPT = 16


def topic_pattern(topic: str) -> str:
    """The read topic a topic is one of: a person's own topics are one pattern
    (``/humans/persons/*/face_id``), so a sender inventing person ids grows nothing."""
    if not topic.startswith("/humans/persons/"):
        return topic
    parts = topic.split("/")
    return f"/humans/persons/*/{parts[4]}" if len(parts) == 5 else topic


def node_of_token(key: str, wire: Wire) -> tuple[str, str] | None:
    """(read topic pattern, node) of an rmw_zenoh publisher's liveliness token, or None:
    ``@ros2_lv/<domain>/<zid>/<nid>/<eid>/MP/<enclave>/<ns>/<node>/<topic>/<type>/...``
    with '/' mangled to '%' inside names (liveliness_utils.cpp)."""
    parts = key.split("/")
    if len(parts) < 11 or parts[0] != "@ros2_lv" or parts[5] != "MP":
        return None
    if parts[1] != str(wire.domain_id):
        return None
    topic = parts[9].replace("%", "/")
    if wire.namespace:
        prefix = "/" + wire.namespace
        if not topic.startswith(prefix + "/"):
            return None
        topic = topic[len(prefix) :]
    ns = parts[7].replace("%", "/").rstrip("/")
    return topic_pattern(topic), cut(f"{ns}/{parts[8]}", 120)


def names(items: list[str]) -> str:
    more = f" and {len(items) - NAMED} more" if len(items) > NAMED else ""
    return ", ".join(cut(i) for i in items[:NAMED]) + more


def where_else(wire: Wire, key: str) -> str:
    """What a key of /tf that this wire does not read says about the robot, as the
    settings that would read it."""
    place = where(key, ("tf",))
    if place is None:
        return "a key of neither format"
    hints = []
    if place.format != wire.format.value:
        hints.append(f"--ros-format {place.format}")
    if place.domain is not None and place.domain != wire.domain_id:
        hints.append(f"--ros-domain-id {place.domain}")
    if place.namespace != wire.namespace:
        hints.append(f"--ros-namespace '{place.namespace}'")
    if hints:
        return ", ".join(hints)
    if place.format == RosFormat.BRIDGE.value:
        return "the same settings (check the router's access control)"
    if place.distro is None:
        return f"a type hash that is neither RIHS01 nor {HASH_NOT_SUPPORTED}"
    return "another type hash (another message version)"


#: The topics (patterns) the service reads: ros2.input's subscriptions.
READ_TOPICS = frozenset(topic for topic, _, _ in TOPICS)


@dataclass
class RobotWatch:
    """What the service has seen of the robot so far (the worker's alone)."""

    wire: Wire
    started: float
    topics: dict[str, int] = field(default_factory=dict)  # read topic pattern -> samples
    strays: list[str] = field(default_factory=list)  # keys of ROS data read nowhere
    time_back: tuple[float, int] | None = None  # (when, how far in ns)
    #: read topic pattern -> publisher GID -> samples, at most PUBLISHERS_KEPT each
    gids: dict[str, dict[bytes, int]] = field(default_factory=dict)
    #: read topic pattern -> node names with a publisher on it (liveliness tokens)
    nodes: dict[str, set[str]] = field(default_factory=dict)
    unnamed: dict[str, int] = field(default_factory=dict)  # topic -> GIDs not kept
    unnamed_nodes: dict[str, int] = field(default_factory=dict)  # topic -> nodes not kept
    #: a tracked person's frame that cannot be looked up -> since when (a list leads its
    #: /tf by a moment: a frame is said missing only once it has been for GRACE_S)
    unplaced: dict[str, float] = field(default_factory=dict)

    def on_input(self, topic: str, publisher: bytes | None = None) -> None:
        topic = topic_pattern(topic)
        self.topics[topic] = self.topics.get(topic, 0) + 1
        if publisher is None:
            return
        gids = self.gids.setdefault(topic, {})
        if publisher in gids or len(gids) < PUBLISHERS_KEPT:
            gids[publisher] = gids.get(publisher, 0) + 1
        else:
            self.unnamed[topic] = self.unnamed.get(topic, 0) + 1

    def on_token(self, key: str, alive: bool) -> None:
        """An rmw_zenoh publisher's liveliness token appeared (or went)."""
        if (read := node_of_token(key, self.wire)) is None or read[0] not in READ_TOPICS:
            return
        topic, node = read
        nodes = self.nodes.setdefault(topic, set())
        if not alive:
            nodes.discard(node)
        elif node in nodes or len(nodes) < PUBLISHERS_KEPT:
            nodes.add(node)
        else:
            self.unnamed_nodes[topic] = self.unnamed_nodes.get(topic, 0) + 1

    def publishers(self) -> dict[str, str]:
        """Per read topic, who publishes it: nodes by their liveliness tokens, and how
        many publishers (GIDs) samples came from."""
        said = {}
        for topic in sorted(self.topics.keys() | self.nodes.keys()):
            nodes = sorted(self.nodes.get(topic, ()))
            gids = len(self.gids.get(topic, {})) + self.unnamed.get(topic, 0)
            named = names(nodes) if nodes else "no node token seen"
            if more := self.unnamed_nodes.get(topic, 0):
                named += f" (+{more} more)"
            said[topic] = f"{named}; samples from {gids} publisher(s)"
        return said

    def on_stray(self, key: str) -> None:
        if key not in self.strays and len(self.strays) < STRAYS_KEPT:
            self.strays.append(key)

    def findings(self, people: People, now: float) -> dict[str, str]:  # (INPUT_BROKEN's codes)
        """The current findings, code -> one line."""
        found: dict[str, str] = {}
        waited = now - self.started >= GRACE_S
        expected = self.wire.subscription("/tf", "tf2_msgs/msg/TFMessage")
        if waited and not self.topics.get("/tf"):
            if self.strays:
                hint = where_else(self.wire, self.strays[0])
                found["ros_input_elsewhere"] = (
                    f"no /tf on {expected}, but ROS 2 data arrives on {names(self.strays)}: "
                    f"to read it, {hint}"
                )
            else:
                what = "nothing" if not self.topics else f"only {names(sorted(self.topics))}"
                found["no_ros_input"] = (
                    f"{what} received from the robot in {now - self.started:.0f} s, no /tf on "
                    f"{expected} nor on any other /tf key: is the robot's router reachable, "
                    "and is something publishing /tf?"
                )
        found |= self._tree(people, waited, now)
        if self.time_back is not None and now - self.time_back[0] < TIME_BACK_SHOWN_S:
            found["time_went_back"] = (
                f"/tf time went back by {self.time_back[1] / 1e9:.1f} s (a recording replayed "
                "again, or the robot's clock reset): TF buffer cleared, as tf2's listener "
                "does, and every person lost, to come back with the new times"
            )
        return found

    def _tree(self, people: People, waited: bool, now: float) -> dict[str, str]:
        tf, base = people.tf, people.base_frame
        frames = tf.frames()
        if not frames or not waited:
            return {}
        if self.time_back is not None and now - self.time_back[0] < GRACE_S:
            return {}  # a recording starting again: its lists lead its /tf for a moment
        roots = tf.roots()
        if not tf.has_frame(base):
            trees = ", ".join(
                f"'{cut(root)}' ({len(tf.descendants(root))} frames)" for root in roots[:NAMED]
            )
            return {
                "base_frame_not_in_tree": (
                    f"base frame '{base}' is not in the robot's TF tree, whose roots are "
                    f"{trees}: set --base-frame to one of its frames, e.g. "
                    f"{names(sorted(frames))}"
                )
            }
        found = {}
        missing, apart = [], []
        for subject in people.subjects():
            frame = people.frame_of(subject)
            if frame is None or not tf.has_frame(frame):
                missing.append(frame or f"{subject} (no face_id or body_id yet)")
                continue
            try:
                tf.lookup(base, frame, 0)
            except TfError:
                if tf.root_of(frame) != tf.root_of(base):
                    apart.append(frame)
        unplaced = set(missing) | set(apart)
        self.unplaced = {f: self.unplaced.get(f, now) for f in unplaced}  # (people's: bounded)
        missing = [f for f in missing if now - self.unplaced.get(f, now) >= GRACE_S]
        apart = [f for f in apart if now - self.unplaced.get(f, now) >= GRACE_S]
        if missing:
            found["tracked_frames_missing"] = (
                f"tracked people have no TF frame yet: {names(missing)} (REP 155: a body's "
                "frame is body_<id> and a face's face_<id>, published on /tf)"
            )
        if apart:
            found["people_not_connected"] = (
                f"the frames of tracked people, {names(apart)}, are in the tree of "
                f"'{cut(tf.root_of(apart[0]))}', and base frame '{base}' in that of "
                f"'{tf.root_of(base)}': nothing links the two trees"
            )
        return found
