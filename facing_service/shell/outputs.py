"""The service's output forms, as types: one ``Output`` protocol, one class per form.

Each form turns what the worker decided (the tracker's changes, a scene's update, and
every period the turn's snapshot) into publications, in the order they must go out, and
brings the sender that puts them on the wire from the publisher thread, with every zenoh
declaration of its own (our JSON keys: ``json_sender``; the robot's topics: declared
publishers and liveliness tokens). The JSON form is always on (it is the contract);
``--output ros2`` adds the robot's topics.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import zenoh

from ..contract.keys import BodyRef
from ..core.records import Changes
from ..core.snapshot import TurnSnapshot
from ..core.social.scene import SceneUpdate
from ..ros2.output import RosOutput
from .json_sender import Heard, JsonSender
from .outbox import Kind, Publication
from .publications import (
    Speaker,
    publications,
    result_publications,
    ros_publications,
    scene_publications,
)
from .robot import Robot
from .ros_bus import RobotPublishers


class Sender(Protocol):
    """Sends one output form's publications, those of its ``kinds`` (on the publisher
    thread)."""

    kinds: frozenset[Kind]

    def send(self, publication: Publication) -> None: ...

    def close(self) -> None: ...


class Output(Protocol):
    def on_changes(self, changes: Changes) -> list[Publication]:
        """What a tracker call's changes call for."""
        ...

    def on_scene(self, update: SceneUpdate) -> list[Publication]:
        """What a frame's scene update calls for."""
        ...

    def tick(self, now: float, snapshot: TurnSnapshot) -> list[Publication]:
        """What time alone calls for (periodic messages), read from the turn's snapshot."""
        ...

    def next_due(self) -> float | None:
        """When ``tick`` has work next (the service's clock); None: never. The worker
        calls ``tick`` only once it is due."""
        ...

    def wake_with(self, wake: Callable[[], None]) -> None:
        """How the output wakes the worker when it has something to say between inputs
        (called once, when the worker's intake exists)."""
        ...

    def start_line(self) -> str:
        """The form's part of the start line ('' for none)."""
        ...

    def sender(self, session: zenoh.Session) -> Sender:
        """The form's sender, declared on the publisher thread."""
        ...


class JsonOutput:
    """Our keys, in JSON (docs/contract.md): results, aggregates, engagement, scenes."""

    def __init__(self, namespace: str, instance: str, max_bodies: int) -> None:
        self._namespace = namespace
        self._us = Speaker(namespace, instance)
        self._capacity = max_bodies
        self._heard = Heard()  # anyone subscribed to results? (the sender's listener says)
        #: Bodies whose result went out since a subscriber appeared (while the re-say
        #: for it is pending): it heard them, so the re-say leaves them out; with the
        #: appearance they were said after (another's re-say leaves none out).
        self._said_since_joined: set[BodyRef] = set()
        self._said_after: int | None = None

    @property
    def results_heard(self) -> bool:
        """Whether anyone subscribes to results (the status says it)."""
        return self._heard.results

    def on_changes(self, changes: Changes) -> list[Publication]:
        heard, due = self._heard.now()  # read once: the listener's thread writes it
        if heard and due is not None:
            if due != self._said_after:  # said after another appearance: not this one's
                self._said_after, self._said_since_joined = due, set()
            self._said_since_joined.update(state.body for state in changes.results)
        return publications(changes, self._us, heard)

    def on_scene(self, update: SceneUpdate) -> list[Publication]:
        return scene_publications(update, self._us)

    def tick(self, now: float, snapshot: TurnSnapshot) -> list[Publication]:
        """A subscriber appeared: every tracked body's current result, at once, but those
        said since zenoh told us of it (they reached it: zenoh's routing knows a
        subscriber before its listener tells us, so the results of poses handled between
        went out and a re-say would repeat them)."""
        due = self._heard.take_due()
        if due is None:
            return []
        said = self._said_since_joined if due == self._said_after else set()
        self._said_after, self._said_since_joined = None, set()
        unsaid = [state for state in snapshot.states if state.body not in said]
        return result_publications(unsaid, self._us)

    def next_due(self) -> float | None:
        return 0.0 if self._heard.now()[1] is not None else None

    def wake_with(self, wake: Callable[[], None]) -> None:
        self._heard.wake = wake

    def start_line(self) -> str:
        return ""

    def sender(self, session: zenoh.Session) -> Sender:
        return JsonSender(session, self._namespace, self._capacity, self._heard)


class RosTopicsOutput:
    """The robot's own topics (``--output ros2``, see ``ros2.output``), in each form the
    robot is answered in."""

    def __init__(
        self, robot: Robot, engagement_rate_hz: float, intents: bool, node_name: str
    ) -> None:
        self._ros = RosOutput(engagement_rate_hz, intents)
        self._robot = robot
        self._node_name = node_name
        self._intents = intents

    def on_changes(self, changes: Changes) -> list[Publication]:
        return ros_publications(self._ros.on_changes(changes))

    def on_scene(self, update: SceneUpdate) -> list[Publication]:
        return ros_publications(self._ros.on_scene(update))

    def tick(self, now: float, snapshot: TurnSnapshot) -> list[Publication]:
        return ros_publications(self._ros.tick(now, snapshot))

    def next_due(self) -> float | None:
        return self._ros.next_tick

    def wake_with(self, wake: Callable[[], None]) -> None:
        return None  # its messages come from inputs and its period

    def start_line(self) -> str:
        topics = "engagement_status, facing lists, groups, gazing, markers" + (
            ", /intents" if self._intents else ""
        )
        return f"; ROS 2 output on the robot's topics ({topics})"

    def sender(self, session: zenoh.Session) -> Sender:
        robot = self._robot
        return RobotPublishers(session, robot.wire, self._node_name, robot.form)
