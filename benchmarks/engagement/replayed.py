"""The labelled recordings as the engagement cross-validation replays them (``crossval``):
each once through the service's own ROS 2 adapter, then per candidate through the
tracker a service with its settings runs, on the recording's clock."""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from facing_service.config.settings import Settings
from facing_service.contract.keys import BodyRef
from facing_service.contract.levels import Level
from facing_service.contract.poses import Rejected
from facing_service.core.records import Changes, PoseSample
from facing_service.core.tracker import Tracker
from facing_service.ros2.input import RosSample, route
from facing_service.ros2.people import People
from facing_service.ros2.wire import Wire

from . import scoring
from .bags import read_bag_raw
from .families import research_tracker
from .scoring import BASE_FRAME, FOLDERS, Labelled, Row, timeline_of

S = 1_000_000_000


@dataclass(frozen=True)
class Step:
    """What one recorded message changed for the person subjects, at its receive time."""

    now_s: float
    poses: tuple[PoseSample, ...]
    lost: tuple[BodyRef, ...]
    time_went_back: bool


@dataclass(frozen=True)
class Recording:
    name: str
    persons: tuple[str, ...]
    label: Level
    start_ns: int
    end_ns: int
    steps: tuple[Step, ...]


def _is_person(subject: str) -> bool:
    return subject.startswith("person_")


def read_recording(recording: Labelled) -> Recording:
    """The recording through the service's own adapter, once (it does not depend on the
    engagement settings). Only person subjects are kept: the ones scored; bodies and
    faces are decided independently of them."""
    people, wire, steps = People(BASE_FRAME), Wire(), []
    times = []
    for topic, typename, t, raw in read_bag_raw(recording.path):
        times.append(t)
        update = route(people, wire, RosSample(wire.key(topic, typename), raw), received_s=t / S)
        if isinstance(update, Rejected):
            continue
        base = people.base_frame
        poses = tuple(p for p in update.poses if _is_person(p.body_id))
        lost = tuple(BodyRef(frame_id=base, body_id=s) for s in update.lost if _is_person(s))
        if poses or lost:
            steps.append(Step(t / S, poses, lost, update.time_back_ns > 0))
    return Recording(
        recording.name, recording.persons, recording.label, times[0], times[-1], tuple(steps)
    )


def events(
    recording: Recording, settings: Settings, research: Mapping[str, Any] | None = None
) -> list[tuple[int, str, Level]]:
    """The engagement events (stamp ns, body, level) a service with ``settings`` says
    (with ``research``: its head's research knobs set)."""
    tracker = research_tracker(settings, research or {})
    return [
        (int(update.stamp), update.body_id, update.level)
        for changes in driven(recording, tracker)
        for update in changes.engagement
        if update.previous is not None
    ]


def driven(recording: Recording, tracker: Tracker) -> Iterator[Changes]:
    """What ``tracker`` says, call by call, fed the recording as the service feeds it:
    each step's poses, then its losses, then what time alone makes due, on the
    recording's clock."""
    for step in recording.steps:
        now = step.now_s
        if step.poses:
            yield tracker.ingest(step.poses, now)
        if step.lost:
            yield tracker.lose(step.lost, now, time_went_back=step.time_went_back)
        for call in tracker.timed(now):
            yield call()


def rows(
    recording: Recording, settings: Settings, research: Mapping[str, Any] | None = None
) -> list[Row]:
    said = events(recording, settings, research)
    return [
        scoring.score(
            recording.name,
            person,
            recording.label,
            timeline_of(said, f"person_{person}", recording.start_ns, recording.end_ns),
        )
        for person in recording.persons
    ]


def load(folders: Sequence[Path] = FOLDERS) -> list[Recording]:
    return [read_recording(recording) for recording in scoring.labelled(folders)]
