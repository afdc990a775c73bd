"""``facing-service replay BAG``: play a ROS 2 bag (sqlite3 ``.db3`` or ``.mcap``) onto
zenoh as a robot would publish it, in rmw_zenoh's format or the bridge's.

Messages go out unchanged (their CDR as recorded), at the recorded pace times ``rate``.
Topics recorded as transient-local (``/tf_static``, the person topics) are published
through zenoh-ext advanced publishers with a cache and publisher detection, as rmw_zenoh
does, so a subscriber that starts later still gets them while the replay runs. In
rmw_zenoh's format each sample carries its attachment (sequence number, source timestamp,
publisher GID). Everything is sent with BLOCK: a replay loses nothing.
"""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import zenoh
from rosbags.highlevel import AnyReader
from rosbags.interfaces import Qos, QosDurability

from ..config.disclosure import zenoh_failure
from ..config.profiles import robot_wire
from ..config.session import zenoh_config
from ..config.settings import Settings
from ..ros2 import types as ros2_types
from ..ros2.wire import Wire
from ..shell.ros_bus import TopicWriter, robot_topic_writer
from .pace import RecordedPace
from .record import Recording


@dataclass
class ReplayStats:
    messages: int = 0
    topics: int = 0
    duration_s: float = 0.0  # of the recording
    elapsed_s: float = 0.0  # of the replay


def _writer(session: zenoh.Session, key: str, wire: Wire, qos: list[Qos]) -> TopicWriter:
    """One topic's writer: with a cache when the topic was recorded transient-local."""
    latched = [q.depth for q in qos if q.durability == QosDurability.TRANSIENT_LOCAL]
    return robot_topic_writer(session, key, wire, max([*latched, 1]) if latched else None)


class Replay:
    """A bag being replayed on a session; ``run`` plays it, ``close`` undeclares (the
    transient-local caches live until then)."""

    def __init__(self, session: zenoh.Session, bag: Path, wire: Wire) -> None:
        self.session = session
        self.bag = Path(bag)
        self.wire = wire
        self._publishers: dict[str, TopicWriter] = {}

    def run(
        self,
        rate: float = 1.0,
        should_stop: Callable[[], bool] = lambda: False,
        on_message: Callable[[str, int], None] | None = None,
    ) -> ReplayStats:
        """Play every message; ``on_message(topic, recorded time ns)`` after each one."""
        stats = ReplayStats()
        with AnyReader([self.bag], default_typestore=ros2_types.typestore()) as reader:
            stats.duration_s = reader.duration / 1e9
            pace = RecordedPace(rate, reader.start_time)
            for connection, timestamp, raw in reader.messages():
                if should_stop():
                    break
                pace.wait(timestamp)
                publisher = self._publishers.get(connection.topic)
                if publisher is None:
                    key = self.wire.key(connection.topic, connection.msgtype)
                    qos = getattr(connection.ext, "offered_qos_profiles", [])
                    publisher = _writer(self.session, key, self.wire, qos)
                    self._publishers[connection.topic] = publisher
                publisher.put(bytes(raw))
                stats.messages += 1
                if on_message is not None:
                    on_message(connection.topic, timestamp)
        stats.topics = len(self._publishers)
        stats.elapsed_s = pace.elapsed_s()
        return stats

    def close(self) -> None:
        for publisher in self._publishers.values():
            publisher.undeclare()
        self._publishers.clear()

    def __enter__(self) -> Replay:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()


def replay(
    settings: Settings, bag: Path, rate: float, record: Path | None, stop: threading.Event
) -> int:
    """``facing-service replay``: play ``bag`` until it ends or ``stop``; with ``record``,
    also record what the service answers. Returns the exit code."""
    wire = robot_wire(settings)
    print(f"replaying {bag} at {rate:g}x in {wire.describe()}")
    try:
        with zenoh.open(zenoh_config(settings)) as session, Replay(session, bag, wire) as player:
            recording = Recording(session, wire, record) if record else None
            stats = player.run(rate, should_stop=stop.is_set)
            if recording is not None:
                time.sleep(0.5)  # the service's last answers on their way
                recorded, topics = recording.close()
                print(f"recorded {recorded} messages on {topics} topics to {recording.path}")
                if not recorded:
                    print(
                        "facing-service replay: recorded nothing: no service answered on the "
                        "robot's topics (is one running with --output ros2, in the same "
                        "--ros-format, domain and namespace, reachable from here?)",
                        file=sys.stderr,
                    )
                    return 1
    except zenoh.ZError as error:
        print(zenoh_failure("replay", error), file=sys.stderr)
        return 1
    except Exception as error:  # rosbags' errors for a folder that is not a bag
        print(f"facing-service replay: {bag}: {error}", file=sys.stderr)
        return 1
    print(
        f"sent {stats.messages} messages on {stats.topics} topics ({stats.duration_s:.1f} s "
        f"recorded) in {stats.elapsed_s:.1f} s"
    )
    return 0
