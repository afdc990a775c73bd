"""Who is who on a ROS4HRI robot: one human, one participant (issue 75).

A robot names each human up to three times: a face (``face_<id>``), a body (``body_<id>``)
and, where hri_person_manager runs, a person whose ``/humans/persons/<id>/face_id`` and
``body_id`` say which face and body are theirs. A tracked person is the participant, and
the face and body it links are where its poses come from; a face or body that no tracked
person links is a participant of its own (REP 155's anonymous case). Which frame for
what: the face says where a person looks (facing, engagement, who faces whom), the body
how they stand (Kendon's F-formation is the lower body's: groups, where to stand), each
falling back to the other.

Pure: the tracked lists and the links as plain values in, frame and subject names out.
"""

from __future__ import annotations

from collections.abc import Mapping, Set

PERSONS = "/humans/persons/tracked"
#: A person's frames, in the order its pose is read from (where it looks): the face, else
#: the body; each with the list that tracks it.
LOOK_ORDER = (("face_", "/humans/faces/tracked"), ("body_", "/humans/bodies/tracked"))

#: tracked list topic -> the ids it tracks now
Tracked = Mapping[str, Set[str]]
#: frame prefix (``face_``, ``body_``) -> person id -> the id it links
Links = Mapping[str, Mapping[str, str]]


def look_frame(person: str, tracked: Tracked, links: Links) -> str | None:
    """The frame a person's pose (where it looks) is read from: its face, else its body, a
    tracked one first (a face lost while its person turns away leaves the body); None
    when it links neither."""
    linked = [
        (prefix + target, target in tracked[topic])
        for prefix, topic in LOOK_ORDER
        if (target := links[prefix].get(person))
    ]
    in_list = [frame for frame, is_tracked in linked if is_tracked]
    return next(iter(in_list or [frame for frame, _ in linked]), None)


def stance_frame(person: str, tracked: Tracked, links: Links) -> str | None:
    """The frame a person stands in when it is not the one it looks from: its body's, None
    otherwise (then it stands where it looks)."""
    body = links["body_"].get(person)
    if body is None or (frame := "body_" + body) == look_frame(person, tracked, links):
        return None
    return frame


def aliases(tracked: Tracked, links: Links, owner: Mapping[str, str]) -> dict[str, str]:
    """Each tracked face or body subject that a tracked person links -> that person's
    subject. A frame another person holds (``owner``: whose pose it is) is not this one's,
    and a frame is one person's alone, the first by id: links cannot amplify."""
    out: dict[str, str] = {}
    for person in sorted(tracked[PERSONS]):
        subject = "person_" + person
        for prefix, topic in LOOK_ORDER:
            target = links[prefix].get(person)
            if target is None or target not in tracked[topic]:
                continue
            frame = prefix + target
            if owner.get(frame, subject) == subject:
                out.setdefault(frame, subject)
    return out
