"""``replay --record OUT``: what the service publishes on the robot's topics (``--output
ros2``), written into a ROS 2 bag (sqlite3, or mcap when OUT ends in ``.mcap``) that ROS
tools open afterwards.

Samples are kept in memory while the replay runs and written, in arrival order, when the
recording closes: a replay is bounded by its bag, and the writer then never runs on
zenoh's callback threads.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
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
    if record is not None:
        folder = bag_folder(record)
        if folder.exists():
            return f"--record {str(record)!r}: {folder} exists (a recording never overwrites)"
        if not folder.parent.is_dir():
            return f"--record {str(record)!r}: no such folder"
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
        from rosbags.rosbag2 import StoragePlugin, Writer

        for subscriber in self._subscribers:
            subscriber.undeclare()
        with self._lock:
            samples = sorted(self._samples, key=lambda s: s[2])
        storage = StoragePlugin.MCAP if self.out.suffix == ".mcap" else StoragePlugin.SQLITE3
        connections = {}
        with Writer(self.path, version=8, storage_plugin=storage) as writer:
            for topic, typename, timestamp, payload in samples:
                if topic not in connections:
                    connections[topic] = writer.add_connection(
                        topic, typename, typestore=ros2_types.typestore()
                    )
                writer.write(connections[topic], timestamp, payload)
        return len(samples), len(connections)
