"""Ids for the faces of a stream of frames: a face keeps its id while it stays near where it
was, and is lost after a moment unseen. Pure: plain numbers in, ids and losses out.

Why so simple: at 15-30 frames a second a face moves a fraction of its own width between
frames, so the nearest face within a width is the same person; a face gone for
``forget_s`` (a blink of the detector, someone walking past) is someone who left, and the
service is told (a DELETE) rather than left to time them out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

#: A face unseen this long is lost (seconds): long enough for a missed frame or two at
#: 15 fps, short enough that the service's view follows the room.
FORGET_S = 0.5
#: A face seen again within this many of its widths of where it was is the same face.
MAX_STEP_WIDTHS = 1.0


@dataclass(frozen=True)
class FaceSeen:
    """One face in one frame: its centre and width in pixels."""

    x: float
    y: float
    width: float


@dataclass
class _Track:
    face: FaceSeen
    seen_s: float


@dataclass
class FaceIds:
    """Gives each face of each frame an id (``f1``, ``f2``, …: ``prefix`` and a count) and
    says who was lost."""

    prefix: str = "f"
    forget_s: float = FORGET_S
    max_step_widths: float = MAX_STEP_WIDTHS
    _tracks: dict[str, _Track] = field(default_factory=dict)
    _next: int = 1

    def update(self, faces: list[FaceSeen], now_s: float) -> tuple[list[str], list[str]]:
        """(the id of each face, index-aligned; the ids lost at ``now_s``). Pairs are made
        nearest first, each track and face used once."""
        pairs = sorted(
            (math.hypot(face.x - track.face.x, face.y - track.face.y), index, face_id)
            for index, face in enumerate(faces)
            for face_id, track in self._tracks.items()
        )
        ids: list[str | None] = [None] * len(faces)
        taken: set[str] = set()
        for step, index, face_id in pairs:
            reach = self.max_step_widths * max(faces[index].width, self._tracks[face_id].face.width)
            if ids[index] is None and face_id not in taken and step <= reach:
                ids[index] = face_id
                taken.add(face_id)
        named = []
        for face, given in zip(faces, ids, strict=True):
            if given is None:
                given = f"{self.prefix}{self._next}"
                self._next += 1
            self._tracks[given] = _Track(face, now_s)
            named.append(given)
        lost = [i for i, t in self._tracks.items() if now_s - t.seen_s > self.forget_s]
        for face_id in lost:
            del self._tracks[face_id]
        return named, lost

    @property
    def given(self) -> int:
        """How many ids were given so far (each face seen, once)."""
        return self._next - 1

    def forget_all(self) -> list[str]:
        """Every id still held (the stream ended): the service is told they left."""
        held = list(self._tracks)
        self._tracks.clear()
        return held
