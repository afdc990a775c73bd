"""``simulate --ros2`` and ``demo --ros2``: a simulated ROS4HRI robot (``robot_scene``) on
zenoh, publishing its topics as rmw_zenoh or the bridge does (``replay``'s writers:
transient-local topics from caches, BLOCK, rmw_zenoh's attachments), and with ``record``
kept as a ROS 2 bag that ``replay`` plays again later, without the simulator."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import zenoh

from ..client.sim import Crowd, paced
from ..ros2.wire import Wire
from ..shell.ros_bus import TopicWriter, robot_topic_writer
from .record import BagMessage, bag_folder, write_bag
from .robot_scene import RobotMessage, RobotScene


@dataclass
class RobotRun:
    """What a simulated robot published."""

    ticks: int = 0
    messages: int = 0
    topics: int = 0
    persons: int = 0  # distinct persons it tracked
    heard: bool = False  # did a subscriber match its /tf


class SimulatedRobot:
    """A ``RobotScene``'s messages on ``session`` in ``wire``'s format; with ``record``,
    also kept for a bag written by ``close``."""

    def __init__(self, session: zenoh.Session, wire: Wire, record: Path | None = None) -> None:
        self.session = session
        self.wire = wire
        self.record = record
        self._writers: dict[str, TopicWriter] = {}
        self._kept: list[BagMessage] = []
        self.run = RobotRun()
        self._persons: set[str] = set()

    def send(self, messages: list[RobotMessage]) -> None:
        now = time.time_ns()
        for message in messages:
            writer = self._writers.get(message.topic)
            if writer is None:
                key = self.wire.key(message.topic, message.typename)
                writer = robot_topic_writer(
                    self.session, key, self.wire, 1 if message.latched else None
                )
                self._writers[message.topic] = writer
            writer.put(message.cdr)
            self.run.messages += 1
            if self.record is not None:
                self._kept.append(
                    BagMessage(message.topic, message.typename, now, message.cdr, message.latched)
                )

    def play(
        self,
        scene: RobotScene,
        rate_hz: float,
        duration_s: float | None,
        should_stop: Callable[[], bool],
    ) -> RobotRun:
        """The scene in real time until ``duration_s`` or ``should_stop``, then its people
        gone (empty lists)."""
        self.send(scene.start())
        try:
            for period in paced(rate_hz, duration_s, should_stop):
                self.send(scene.step(period))
                self._persons.update(scene.persons())
                self.run.ticks += 1
                if not self.run.heard and (tf := self._writers.get("/tf")) is not None:
                    self.run.heard = tf.matched()
        finally:
            self.send(scene.stop())
        self.run.persons = len(self._persons)
        return self.run

    def close(self) -> tuple[int, int] | None:
        """Undeclare everything; with ``record``, write the bag: ``(messages, topics)``."""
        self.run.topics = len(self._writers)
        for writer in self._writers.values():
            writer.undeclare()
        self._writers.clear()
        if self.record is None:
            return None
        return write_bag(self.record, self._kept)


class RobotFeed:
    """``demo --ros2``'s feed: a simulated robot publishing on the demo's router until the
    demo stops; ``report`` then says what it published and recorded."""

    def __init__(
        self, wire: Wire, crowd: Crowd, base_frame: str, rate_hz: float, record: Path | None
    ) -> None:
        self.wire = wire
        self.scene = RobotScene(crowd, base_frame)
        self.rate_hz = rate_hz
        self.record = record
        self.run = RobotRun()
        self.recorded: tuple[int, int] | None = None

    def __call__(self, session: zenoh.Session, should_stop: Callable[[], bool]) -> None:
        print(f"demo: a simulated ROS 2 robot running ROS4HRI publishes its people (/tf, "
              f"/tf_static, /humans/*) in {self.wire.describe()}; the service reads them "
              f"(--input ros2) and answers on the robot's topics (--output ros2)",
              flush=True)  # fmt: skip
        robot = SimulatedRobot(session, self.wire, self.record)
        try:
            self.run = robot.play(self.scene, self.rate_hz, None, should_stop)
        finally:
            self.recorded = robot.close()

    def report(self) -> None:
        print(f"the robot published {self.run.messages} messages on {self.run.topics} topics; "
              f"{self.run.persons} persons tracked")  # fmt: skip
        if self.recorded is not None and self.record is not None:
            print(recorded_line(self.recorded, self.record))


def recorded_line(recorded: tuple[int, int], record: Path) -> str:
    """What a recording of the robot holds, and how to play it again."""
    folder = bag_folder(record)
    return (
        f"recorded {recorded[0]} messages on {recorded[1]} topics to {folder}: play it to "
        f"a service (run --input ros2) with facing-service replay {folder}"
    )
