"""A synthetic crowd: people walking around a robot, stopping, turning toward it and away,
appearing and leaving, seen through a noisy body tracker.

Pure and deterministic: ``Crowd.step(dt)`` advances the world and returns what a tracker
would publish for that tick (poses, and ids that were lost), all from one seeded random
generator, so the same seed always gives the same poses. ``simulate`` is the thin shell
that publishes a crowd over zenoh at a rate.
"""

from __future__ import annotations

import json
import math
import random
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from enum import Enum
from typing import cast

import zenoh

from ..config.disclosure import public_endpoints
from ..contract import keys
from ..contract.poses import pose_dict, yaw_rotation
from ..contract.stamps import Time

#: The area people move in around the robot (metres, base frame; the robot at the origin).
AREA_M = 4.0
SPEED_M_S = 0.9
#: Tracker-like noise, per published pose.
YAW_NOISE_DEG = 3.0
POSITION_NOISE_M = 0.03


class Activity(str, Enum):
    WALKING = "walking"
    STOPPED = "stopped"
    FACING = "facing"  # stopped, turned toward the robot
    LEAVING = "leaving"


@dataclass
class Walker:
    body_id: str
    x: float
    y: float
    yaw_deg: float
    activity: Activity
    until_s: float  # when the current activity ends
    goal: tuple[float, float] = (0.0, 0.0)


@dataclass(frozen=True)
class TrackedPose:
    body_id: str
    x: float
    y: float
    yaw_deg: float
    sec: int
    nanosec: int


@dataclass(frozen=True)
class Tick:
    """What the tracker publishes at one instant (not a coordinate frame: those are
    ``frame_id``)."""

    poses: list[TrackedPose]
    lost: list[str]


@dataclass
class Crowd:
    people: int = 5
    seed: int = 0
    #: Time at which the crowd starts (the stamps' origin), in seconds.
    start_s: float = 1_700_000_000.0
    _rng: random.Random = field(init=False)
    _now: float = field(init=False, default=0.0)
    _walkers: dict[str, Walker] = field(init=False, default_factory=dict)
    _next_id: int = field(init=False, default=1)

    def __post_init__(self) -> None:
        self._rng = random.Random(self.seed)
        for _ in range(self.people):
            self._arrive()

    @property
    def now(self) -> float:
        return self._now

    def present(self) -> list[str]:
        """The ids of the people there now."""
        return list(self._walkers)

    def step(self, dt: float) -> Tick:
        """Advance by ``dt`` seconds; the tracker's view of the new instant."""
        self._now += dt
        lost = []
        for person in list(self._walkers.values()):
            self._move(person, dt)
            if person.activity is Activity.LEAVING and math.hypot(person.x, person.y) > AREA_M:
                del self._walkers[person.body_id]
                lost.append(person.body_id)
        while len(self._walkers) < self.people:
            self._arrive()
        # integer nanoseconds: stamps never step back through a rounding carry
        sec, nanosec = divmod(round((self.start_s + self._now) * 1e9), 1_000_000_000)
        rng = self._rng
        poses = [
            TrackedPose(
                p.body_id,
                p.x + rng.gauss(0.0, POSITION_NOISE_M),
                p.y + rng.gauss(0.0, POSITION_NOISE_M),
                p.yaw_deg + rng.gauss(0.0, YAW_NOISE_DEG),
                sec,
                nanosec,
            )
            for p in self._walkers.values()
        ]
        return Tick(poses, lost)

    def _arrive(self) -> None:
        rng = self._rng
        angle = rng.uniform(0, 2 * math.pi)
        radius = rng.uniform(1.5, AREA_M)
        person = Walker(
            body_id=f"p{self._next_id}",
            x=radius * math.cos(angle),
            y=radius * math.sin(angle),
            yaw_deg=rng.uniform(-180, 180),
            activity=Activity.WALKING,
            until_s=self._now,
        )
        self._next_id += 1
        self._walkers[person.body_id] = person
        self._choose(person)

    def _choose(self, person: Walker) -> None:
        """Pick the next activity: walk somewhere, stop, face the robot, or leave."""
        rng = self._rng
        roll = rng.random()
        if roll < 0.35:
            person.activity = Activity.WALKING
            angle, radius = rng.uniform(0, 2 * math.pi), rng.uniform(0.8, AREA_M - 0.5)
            person.goal = (radius * math.cos(angle), radius * math.sin(angle))
            person.until_s = self._now + rng.uniform(2.0, 6.0)
        elif roll < 0.55:
            person.activity = Activity.STOPPED
            person.yaw_deg += rng.uniform(-120, 120)
            person.until_s = self._now + rng.uniform(1.0, 4.0)
        elif roll < 0.9:
            person.activity = Activity.FACING
            person.until_s = self._now + rng.uniform(2.0, 6.0)
        else:
            person.activity = Activity.LEAVING
            angle = math.atan2(person.y, person.x) + rng.uniform(-0.5, 0.5)
            person.goal = (2 * AREA_M * math.cos(angle), 2 * AREA_M * math.sin(angle))
            person.until_s = math.inf

    def _move(self, person: Walker, dt: float) -> None:
        if self._now >= person.until_s:
            self._choose(person)
        if person.activity in (Activity.WALKING, Activity.LEAVING):
            dx, dy = person.goal[0] - person.x, person.goal[1] - person.y
            distance = math.hypot(dx, dy)
            if distance < 0.05 and person.activity is Activity.WALKING:
                person.until_s = self._now  # arrived: choose again next step
                return
            step = min(distance, SPEED_M_S * dt)
            person.x += step * dx / max(distance, 1e-9)
            person.y += step * dy / max(distance, 1e-9)
            person.yaw_deg = math.degrees(math.atan2(dy, dx))
        elif person.activity is Activity.FACING:
            toward = math.degrees(math.atan2(-person.y, -person.x))
            turn = (toward - person.yaw_deg + 180) % 360 - 180
            person.yaw_deg += max(-180 * dt, min(180 * dt, turn))  # turns at 180 deg/s


def pose_message(pose: TrackedPose, frame_id: str) -> bytes:
    """The tracker's payload: a TransformStamped of ``body_<id>`` in ``frame_id``."""
    return json.dumps(
        pose_dict(
            pose.body_id,
            frame_id,
            Time.of(pose.sec, pose.nanosec),
            (pose.x, pose.y, 0.0),
            yaw_rotation(pose.yaw_deg),
        )
    ).encode()


def simulate(
    publish: Callable[[str, bytes | None], None],
    crowd: Crowd,
    frame_id: str,
    namespace: str = "hri",
    rate_hz: float = 30.0,
    duration_s: float | None = None,
    should_stop: Callable[[], bool] = lambda: False,
    clock: Callable[[], float] = time.monotonic,
    sleep: Callable[[float], None] = time.sleep,
) -> int:
    """Publish ``crowd`` in real time: ``publish(key, payload)`` for each pose and
    ``publish(key, None)`` (a DELETE) for each person lost, and for everyone still there
    when it stops (a tracker that stops says its people are gone: a service would
    otherwise read the stop as a stalled link and hold them). Returns the ticks published.
    ``clock`` and ``sleep`` pace it (tests give their own, so they need not wait)."""
    ticks = 0
    try:
        for period in paced(rate_hz, duration_s, should_stop, clock, sleep):
            tick = crowd.step(period)
            for pose in tick.poses:
                publish(
                    keys.pose_key(namespace, body_id=pose.body_id, frame_id=frame_id),
                    pose_message(pose, frame_id),
                )
            for body_id in tick.lost:
                publish(keys.pose_key(namespace, body_id=body_id, frame_id=frame_id), None)
            ticks += 1
    finally:
        for body_id in crowd.present():
            publish(keys.pose_key(namespace, body_id=body_id, frame_id=frame_id), None)
    return ticks


def paced(
    rate_hz: float,
    duration_s: float | None,
    should_stop: Callable[[], bool],
    clock: Callable[[], float] = time.monotonic,
    sleep: Callable[[float], None] = time.sleep,
) -> Iterator[float]:
    """Ticks at ``rate_hz`` in real time until ``duration_s`` or ``should_stop()``: yields
    the period for each tick's work, then sleeps until the next is due (a tick that ran
    late is caught up, not skipped)."""
    period = 1.0 / rate_hz
    started = clock()
    ticks = 0
    while not should_stop() and (duration_s is None or ticks * period < duration_s):
        yield period
        ticks += 1
        if (delay := started + ticks * period - clock()) > 0:
            sleep(delay)


class TrackerPublisher:
    """Publishes as a body tracker should: poses with BLOCK (zenoh's default, DROP, loses
    them on the sending side under load), ``None`` as a DELETE. Counts what went out, and
    how much of it a subscriber heard (zenoh's matching status, one declared publisher per
    body: poses sent to nowhere were once reported as published), and with
    ``progress_every_s`` says so (``say``) that often."""

    def __init__(
        self,
        session: zenoh.Session,
        progress_every_s: float | None = None,
        say: Callable[[str], None] = print,
    ) -> None:
        self._session = session
        self._every_s = progress_every_s
        self._say = say
        self._publishers: dict[str, zenoh.Publisher] = {}
        self.poses = self.deletes = self.heard = 0
        self._started = self._reported = time.monotonic()

    def __call__(self, key: str, payload: bytes | None) -> None:
        if payload is None:
            publisher = self._publishers.pop(key, None)
            if publisher is None:
                self._session.delete(key, congestion_control=zenoh.CongestionControl.BLOCK)
            else:
                publisher.delete()
                publisher.undeclare()
            self.deletes += 1
        else:
            if (publisher := self._publishers.get(key)) is None:
                publisher = self._publishers[key] = self._session.declare_publisher(
                    key,
                    encoding=zenoh.Encoding.APPLICATION_JSON,
                    congestion_control=zenoh.CongestionControl.BLOCK,
                )
            publisher.put(payload)
            self.poses += 1
            # eclipse-zenoh's stub types the property bool; it returns a MatchingStatus
            self.heard += cast(zenoh.MatchingStatus, publisher.matching_status).matching
        if (
            self._every_s is not None
            and (now := time.monotonic()) - self._reported >= self._every_s
        ):
            self._reported = now
            rate = self.poses / (now - self._started)
            self._say(
                f"published {self.poses} poses ({rate:.0f}/s) and {self.deletes} deletes"
                + ("" if self.heard else "; no subscriber has heard any yet")
            )

    def close(self) -> None:
        """Undeclare every body's publisher (the session's close would too)."""
        for publisher in self._publishers.values():
            publisher.undeclare()
        self._publishers.clear()


def nobody_heard(command: str, key: str, namespace: str, connect: list[str]) -> str:
    """The line a command says when no subscriber heard any pose it published on ``key``
    (to ``connect``'s endpoints): sent to nowhere is not a success."""
    where = public_endpoints(connect)
    return (
        f"facing-service {command}: no subscriber heard any pose on {key}: is a facing "
        f"service running in namespace '{namespace}', "
        + (f"reachable at {where}?" if where else "found by scouting from here?")
    )
