"""Who is who on a ROS4HRI robot: one human, one participant, derived whole from the
robot's tracked lists and person links, never kept beside them.

A robot names each human up to three times: a face (``face_<id>``), a body (``body_<id>``)
and, where hri_person_manager runs, a person whose ``/humans/persons/<id>/face_id`` and
``body_id`` say which face and body are theirs. A tracked person is the participant, and
the face and body it links are where its poses come from; a face or body that no tracked
person links is a participant of its own (REP 155's anonymous case). Which frame for
what: the face says where a person looks (facing, engagement, who faces whom), the body
how they stand (Kendon's F-formation is the lower body's: groups, where to stand).

Invariants, each true of every ``Presence`` ``derive`` returns:

- a face or body frame belongs to at most one tracked person: of those linking it, the
  one whose link was made last (a person manager moving a face from an anonymous person
  to a recognised one moves it at once, with no refusal; cloned ids take turns at one
  frame and never multiply its results);
- a tracked face or body that a tracked person holds is never a participant of its own;
- a person looks from its face, else its body: the tracked ones it holds, or, when no
  list tracks either, the ones it links; the caller falls back along ``looks`` when a
  frame cannot be looked up yet;
- a person stands in its body only while the body is tracked (a lost body's last
  transform is where the person *was*), else where it looks.

Pure: the tracked lists and the links as plain values in, a frozen value out. The cost
is one pass over the lists and links: tens of microseconds at 50 ids, about 10 ms at
10 000 (``benchmarks``), paid only when a list's members or a link change.
"""

from __future__ import annotations

from collections.abc import Mapping, Set
from dataclasses import dataclass

PERSONS = "/humans/persons/tracked"
#: A person's frames, in the order its pose is read from (where it looks): the face, else
#: the body; each with the list that tracks it.
LOOK_ORDER = (("face_", "/humans/faces/tracked"), ("body_", "/humans/bodies/tracked"))
BODIES = "/humans/bodies/tracked"

#: tracked list topic -> the ids it tracks now
Tracked = Mapping[str, Set[str]]
#: frame prefix (``face_``, ``body_``) -> person id -> the id it links, oldest link first
Links = Mapping[str, Mapping[str, str]]


@dataclass(frozen=True, slots=True)
class Participant:
    """One human as the service names it (``person_<id>``, ``face_<id>``, ``body_<id>``):
    the frames it may look from, in order, and the body it stands in when apart."""

    looks: tuple[str, ...]
    stands: str | None = None


@dataclass(frozen=True, slots=True)
class Presence:
    """Who is there now, as whom: participants by subject, who holds each frame, and the
    participants whose pose a change of each frame can change."""

    participants: Mapping[str, Participant]
    holder: Mapping[str, str]  # face or body frame -> the person subject it belongs to
    by_frame: Mapping[str, Set[str]]


def derive(tracked: Tracked, links: Links) -> Presence:
    """Who is there, from the lists and links alone (see the module's invariants)."""
    persons = tracked[PERSONS]
    holder: dict[str, str] = {}
    for prefix, _ in LOOK_ORDER:
        for person, target in links[prefix].items():  # oldest link first: the last wins
            if person in persons:
                holder[prefix + target] = "person_" + person
    participants: dict[str, Participant] = {}
    by_frame: dict[str, set[str]] = {}
    faces, bodies = links["face_"], links["body_"]
    faces_tracked, bodies_tracked = tracked[LOOK_ORDER[0][1]], tracked[BODIES]
    for person in persons:
        subject = "person_" + person
        on: list[str] = []  # the frames it holds that a list tracks, face first
        off: list[str] = []  # those no list tracks
        face, body = faces.get(person), bodies.get(person)
        if face is not None and holder["face_" + face] == subject:
            (on if face in faces_tracked else off).append("face_" + face)
        if body is not None and holder["body_" + body] == subject:
            (on if body in bodies_tracked else off).append("body_" + body)
        looks = tuple(on or off)
        stands = on[1] if len(on) == 2 else None  # its tracked body, apart from its face
        participants[subject] = Participant(looks, stands)
        for frame in looks:
            by_frame.setdefault(frame, set()).add(subject)
    for prefix, topic in LOOK_ORDER:
        for ros_id in tracked[topic]:
            if (frame := prefix + ros_id) not in holder:
                participants[frame] = Participant((frame,))
                by_frame.setdefault(frame, set()).add(frame)
    return Presence(participants, holder, by_frame)
