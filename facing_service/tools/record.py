"""ROS 2 bags written: ``replay --record OUT``, what the service publishes on the robot's
topics (``--output ros2``), and ``simulate --ros2 --record OUT``, a simulated robot's own
topics; sqlite3, or mcap when OUT ends in ``.mcap``, which ROS tools open afterwards and
``replay`` plays again.

Samples are kept in memory while the replay runs and written, in arrival order, when the
recording closes: a replay is bounded by its bag, and the writer then never runs on
zenoh's callback threads.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import zenoh

from ..ros2 import types as ros2_types
from ..ros2.output import PUBLISHED_TOPICS
from ..ros2.wire import Wire


def bag_folder(out: Path) -> Path:
    """The rosbag2 folder a recording to ``out`` makes: ``OUT/``, or for ``OUT.mcap``
    the folder ``OUT/`` holding ``OUT.mcap``."""
    return out.with_suffix("") if out.suffix == ".mcap" else out


#: A rosbag2's storage files, which replay also takes in place of the bag's folder.
BAG_FILES = (".db3", ".mcap")


def replay_refusal(bag: Path, record: Path | None) -> str | None:
    """Why ``replay BAG [--record OUT]`` cannot start (one line naming the argument), or
    None. Checked before anything opens: a recording never overwrites."""
    if not bag.exists():
        return f"BAG {str(bag)!r}: no such file or folder"
    if bag.is_dir() and not (bag / "metadata.yaml").is_file():
        inside = sorted(d.name for d in bag.iterdir() if (d / "metadata.yaml").is_file())
        if inside:
            named = ", ".join(inside[:8]) + (
                f" and {len(inside) - 8} more" if len(inside) > 8 else ""
            )
            return f"BAG {str(bag)!r} is a folder of recordings, not one: replay one of {named}"
        return f"BAG {str(bag)!r}: not a rosbag2 folder (it has no metadata.yaml)"
    if bag.is_file() and bag.suffix not in BAG_FILES:
        return (
            f"BAG {str(bag)!r}: not a rosbag2 (a folder with metadata.yaml, or its .db3 or .mcap)"
        )
    return None if record is None else record_refusal(record)


def record_refusal(record: Path) -> str | None:
    """Why ``--record OUT`` (a ROS 2 bag: the folder ``bag_folder(OUT)``) cannot be
    written, or None."""
    return new_path_refusal("--record", record, bag_folder(record))


def new_path_refusal(flag: str, given: Path, made: Path) -> str | None:
    """Why a recording asked for as ``flag given`` cannot make ``made`` (one line naming
    the flag), or None: a recording never overwrites, and its folder must be there."""
    if made.exists():
        return f"{flag} {str(given)!r}: {made} exists (a recording never overwrites)"
    if not made.parent.is_dir():
        return f"{flag} {str(given)!r}: no such folder"
    return None


class Recording:
    """Subscribes to the service's ROS 2 output on ``session``; ``close`` writes the bag
    and returns how many messages it holds."""

    def __init__(self, session: zenoh.Session, wire: Wire, out: Path) -> None:
        self.out = out
        self.path = bag_folder(out)
        if self.path.exists():
            raise FileExistsError(f"{self.path} exists: a recording never overwrites")
        self.wire = wire
        self._lock = threading.Lock()
        self._samples: list[tuple[str, str, int, bytes]] = []
        self._subscribers = [
            session.declare_subscriber(wire.subscription(topic, typename), self._keep(typename))
            for topic, typename in PUBLISHED_TOPICS
        ]

    def _keep(self, typename: str) -> Callable[[zenoh.Sample], None]:
        """The callback keeping the samples of one output topic (of ``typename``)."""

        def on_sample(sample: zenoh.Sample) -> None:
            topic = self.wire.topic_of(str(sample.key_expr))
            if topic is None or sample.kind != zenoh.SampleKind.PUT:
                return
            with self._lock:
                self._samples.append((topic, typename, time.time_ns(), sample.payload.to_bytes()))

        return on_sample

    def close(self) -> tuple[int, int]:
        """Stop recording, write the bag: ``(messages, topics)``."""
        for subscriber in self._subscribers:
            subscriber.undeclare()
        with self._lock:
            samples = sorted(self._samples, key=lambda s: s[2])
        return write_bag(self.out, [BagMessage(*sample) for sample in samples])


@dataclass(frozen=True, slots=True)
class BagMessage:
    """One message of a bag: its topic and type, when (ns), its CDR; ``latched``: on a
    transient-local topic, so that a replay serves it from a cache as the robot did."""

    topic: str
    typename: str
    timestamp_ns: int
    cdr: bytes
    latched: bool = False


def write_bag(out: Path, messages: Sequence[BagMessage]) -> tuple[int, int]:
    """A new rosbag2 of ``messages`` in their order: the folder ``bag_folder(out)``, in
    mcap when ``out`` ends in ``.mcap``, else sqlite3. Returns ``(messages, topics)``."""
    from rosbags.interfaces import (
        Qos,
        QosDurability,
        QosHistory,
        QosLiveliness,
        QosReliability,
        QosTime,
    )
    from rosbags.rosbag2 import StoragePlugin, Writer

    never = QosTime(sec=2147483647, nsec=4294967295)  # rosbag2's "infinite"
    latched = Qos(QosHistory.KEEP_LAST, 1, QosReliability.RELIABLE,
                  QosDurability.TRANSIENT_LOCAL, never, never, QosLiveliness.AUTOMATIC,
                  never, False)  # fmt: skip
    storage = StoragePlugin.MCAP if out.suffix == ".mcap" else StoragePlugin.SQLITE3
    connections = {}
    with Writer(bag_folder(out), version=8, storage_plugin=storage) as writer:
        for message in messages:
            if message.topic not in connections:
                connections[message.topic] = writer.add_connection(
                    message.topic,
                    message.typename,
                    typestore=ros2_types.typestore(),
                    offered_qos_profiles=[latched] if message.latched else [],
                )
            writer.write(connections[message.topic], message.timestamp_ns, message.cdr)
    return len(messages), len(connections)
