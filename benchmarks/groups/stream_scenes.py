"""Streams made here: what a memory of the last seconds must fix, and what it
must not break. Not data: each is a sequence of frames at a stated spacing, with the true
groups of every frame, replayed as the shared sequences are (``replay.replay``).

- **90-degree flicker**: a ring of four and a ring of three, each person's heading the
  true one (into their ring) rounded down or up to a 90-degree step, changing between the
  two about one reading in three (as GDet's and CoffeeBreak's annotations do); two loners.
  One reading a second.
- **walking through**: a conversation of three; a fourth person walks past at 1.2 m/s
  through the gap beside it, without stopping. Ten readings a second (a tracker).
- **group forming**: one person walks up to another, who turns to them as they stop 1.2 m
  away; the frames from the stop on show a group.
- **member leaving**: a ring of four; one turns and walks away at 1.2 m/s.
- **group dissolving**: a pair; both turn and walk apart.
- **two pairs one frame**: two pairs 2.4 m apart; for one reading (a second) all four face
  the middle between them, then back: two pairs throughout.

Positions in metres, headings in radians, the robot at the origin (added by the scene)
and kept out of every conversation (every scene stands 2 m or more ahead of it).
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass

import numpy as np

from .sequence_frame import Frame

QUARTER = math.pi / 2
WALK_MPS = 1.2


@dataclass(frozen=True)
class Stream:
    """A made stream: its frames, the seconds between them, and how long its first
    frame's people stood so before it (the service has seen them: not judged)."""

    frames: list[Frame]
    spacing_s: float
    before_s: float = 5.0


def _frame(
    standing: list[tuple[float, float, float]], truth: tuple[frozenset[int], ...] = ()
) -> Frame:
    """One frame: everyone (x, y, heading) numbered in order, and the true groups."""
    xy = np.array([(x, y) for x, y, _ in standing])
    return Frame(tuple(range(len(standing))), xy, np.array([h for _, _, h in standing]), truth)


def _ring(centre: tuple[float, float], count: int, radius: float, start: float) -> list[tuple]:
    """``count`` people on a ring, each facing its centre."""
    out = []
    for k in range(count):
        a = start + 2 * math.pi * k / count
        x, y = centre[0] + radius * math.cos(a), centre[1] + radius * math.sin(a)
        out.append((x, y, a + math.pi))
    return out


def flicker(rng: random.Random, frames: int = 60) -> Stream:
    """Two rings whose 90-degree headings flicker between the steps either side of the
    true one; two loners facing away from everyone."""
    people = _ring((4.0, -1.5), 4, 0.8, rng.uniform(0.3, 1.2)) + _ring(
        (4.0, 2.0), 3, 0.7, rng.uniform(0.3, 1.2)
    )
    people += [(8.5, -4.0, 0.0), (8.5, 4.5, QUARTER)]
    truth = (frozenset(range(4)), frozenset(range(4, 7)))
    up = [rng.random() < 0.5 for _ in people]
    out = []
    for _ in range(frames):
        standing = []
        for k, (x, y, h) in enumerate(people):
            if k < 7 and rng.random() < 1 / 3:
                up[k] = not up[k]
            step = math.floor(h / QUARTER) + (1 if up[k] else 0)
            standing.append((x, y, step * QUARTER if k < 7 else h))
        out.append(_frame(standing, truth))
    return Stream(out, 1.0)


def walking_through(rng: random.Random, seconds: float = 12.0) -> Stream:
    """A conversation of three; a walker crossing beside it at walking pace."""
    group = _ring((4.0, 0.0), 3, 0.7, rng.uniform(0, 2 * math.pi))
    out, dt = [], 0.1
    for k in range(round(seconds / dt)):
        y = -6.0 + WALK_MPS * k * dt
        walker = (4.0 + 1.1, y, QUARTER)  # along +y, passing 0.4 m outside the ring
        out.append(_frame([*group, walker], (frozenset(range(3)),)))
    return Stream(out, dt)


def forming(seconds: float = 12.0, at_s: float = 3.0) -> Stream:
    """One person stands looking elsewhere (+y); another walks up to them at 1 m/s, facing
    them, and stops 1.2 m away at ``at_s``, when the first turns to face them."""
    out, dt = [], 0.1
    for k in range(round(seconds / dt)):
        t = k * dt
        b = (3.0 + 1.2 + (at_s - min(t, at_s)) * 1.0, 1.0, math.pi)
        a = (3.0, 1.0, 0.0 if t >= at_s else QUARTER)
        out.append(_frame([a, b], (frozenset({0, 1}),) if t >= at_s else ()))
    return Stream(out, dt)


def leaving(seconds: float = 20.0, at_s: float = 10.0) -> Stream:
    """A ring of four; at ``at_s`` one of them turns outwards and walks away."""
    ring = _ring((4.0, 0.0), 4, 0.7, 0.3)
    out, dt = [], 0.1
    for k in range(round(seconds / dt)):
        t = k * dt
        standing = list(ring)
        if t >= at_s:
            x, y, h = ring[0]
            away = h + math.pi
            walked = WALK_MPS * (t - at_s)
            standing[0] = (x + walked * math.cos(away), y + walked * math.sin(away), away)
        truth = frozenset(range(4)) if t < at_s else frozenset(range(1, 4))
        out.append(_frame(standing, (truth,)))
    return Stream(out, dt)


def dissolving(seconds: float = 20.0, at_s: float = 10.0) -> Stream:
    """A pair face to face; at ``at_s`` both turn away and walk apart."""
    out, dt = [], 0.1
    for k in range(round(seconds / dt)):
        t = k * dt
        walked = WALK_MPS * max(0.0, t - at_s)
        if t < at_s:
            standing = [(3.5, 1.0, 0.0), (4.7, 1.0, math.pi)]
        else:
            standing = [(3.5 - walked, 1.0, math.pi), (4.7 + walked, 1.0, 0.0)]
        out.append(_frame(standing, (frozenset({0, 1}),) if t < at_s else ()))
    return Stream(out, dt)


def two_pairs_one_frame(frames: int = 30, at: int = 15) -> Stream:
    """Two pairs face to face, 2.4 m apart; in frame ``at`` all four face the middle."""
    pairs = [(3.0, -1.2), (4.2, -1.2), (3.0, 1.2), (4.2, 1.2)]
    middle = (3.6, 0.0)
    truth = (frozenset({0, 1}), frozenset({2, 3}))
    out = []
    for k in range(frames):
        standing = []
        for i, (x, y) in enumerate(pairs):
            if k == at:
                h = math.atan2(middle[1] - y, middle[0] - x)
            else:
                h = 0.0 if i % 2 == 0 else math.pi
            standing.append((x, y, h))
        out.append(_frame(standing, truth))
    return Stream(out, 1.0)


def streams(seed: int = 70) -> dict[str, Stream]:
    rng = random.Random(seed)
    return {
        "90-degree flicker": flicker(rng),
        "walking through": walking_through(rng),
        "group forming": forming(),
        "member leaving": leaving(),
        "group dissolving": dissolving(),
        "two pairs one frame": two_pairs_one_frame(),
    }
