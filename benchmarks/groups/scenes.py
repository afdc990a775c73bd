"""Scenes made here, each modelled on one way the grouping failed on scenes kept outside the
project: a dense room of posters, a wide circle of five with 90-degree
headings, loners standing near each other; a dense room of large groups (people 0.6 m
apart, groups of four to six), a circle of five or six 0.8 m apart with headings rounded
to 45 or 90 degrees, pairs side by side who are not a group. Not data: a rule that wins on
the shared sequences and falls to "no groups" on one of them is not chosen
(``groups.preferred``).

Deterministic for a seed. Positions in metres, headings in radians, in ``sequence_frame.Frame``'s
layout (the robot is added by ``groups.run`` at the origin, as everywhere).
"""

from __future__ import annotations

import math
import random

import numpy as np

from .sequence_frame import Frame

QUARTER = math.pi / 2


def _frame(
    positions: list[tuple[float, float]],
    headings: list[float],
    truth: tuple[frozenset[int], ...] = (),
) -> Frame:
    """One made frame: everyone numbered in order, and the true groups."""
    return Frame(tuple(range(len(positions))), np.array(positions), np.array(headings), truth)


def _facing(source: tuple[float, float], target: tuple[float, float]) -> float:
    return math.atan2(target[1] - source[1], target[0] - source[0])


def posters(rng: random.Random, frames: int = 40, noise_deg: float = 25.0) -> list[Frame]:
    """Five posters side by side, 1.9 m apart: at each a presenter faces an audience of
    two or three standing in an arc 1.1 m away, who face the presenter; neighbouring
    audiences stand about 0.6 m apart, so the crowd is denser than its groups. Headings
    continuous, with ``noise_deg`` of noise (body orientation from a tracker)."""
    out = []
    for _ in range(frames):
        positions: list[tuple[float, float]] = []
        headings: list[float] = []
        truth = []
        for poster in range(5):
            presenter = (1.5 + 1.9 * poster, 2.0)
            size = 3 if poster % 2 == 0 else 2
            audience = [
                (
                    presenter[0] + 1.1 * math.cos(math.radians(-90 + (a - (size - 1) / 2) * 40)),
                    presenter[1] + 1.1 * math.sin(math.radians(-90 + (a - (size - 1) / 2) * 40)),
                )
                for a in range(size)
            ]
            middle = tuple(np.mean(audience, axis=0))
            truth.append(frozenset(range(len(positions), len(positions) + size + 1)))
            for person, target in [(presenter, middle), *((a, presenter) for a in audience)]:
                positions.append(person)
                headings.append(_facing(person, target) + math.radians(rng.gauss(0, noise_deg)))
        out.append(_frame(positions, headings, tuple(truth)))
    return out


def wide_circle(rng: random.Random, frames: int = 40) -> list[Frame]:
    """Five people on a circle of 1.5 m radius facing its centre, headings quantised to
    90 degrees (as GDet annotates them), and two loners 3 m or more away."""
    out = []
    for _ in range(frames):
        start = rng.uniform(0, 2 * math.pi)
        positions, headings = [], []
        for k in range(5):
            a = start + 2 * math.pi * k / 5 + rng.gauss(0, 0.1)
            p = (3.0 + 1.5 * math.cos(a), 1.5 * math.sin(a))
            true = _facing(p, (3.0, 0.0)) + math.radians(rng.gauss(0, 10.0))
            positions.append(p)
            headings.append(round(true / QUARTER) * QUARTER)
        positions += [(3.0, 4.5), (6.5, -3.0)]
        headings += [rng.randrange(4) * QUARTER for _ in range(2)]
        out.append(_frame(positions, headings, (frozenset(range(5)),)))
    return out


def loners(rng: random.Random, frames: int = 60) -> list[Frame]:
    """Two to eight people at least 1.2 m apart, each facing a random one of four ways:
    nobody is in a group (the "no groups" answer scores 1)."""
    out = []
    for _ in range(frames):
        count = rng.randint(2, 8)
        positions: list[tuple[float, float]] = []
        while len(positions) < count:
            q = (rng.uniform(1.0, 6.0), rng.uniform(-3.0, 3.0))
            if all(math.dist(q, o) >= 1.2 for o in positions):
                positions.append(q)
        headings = [rng.randrange(4) * QUARTER for _ in positions]
        out.append(_frame(positions, headings))
    return out


def _ring(
    rng: random.Random, centre: tuple[float, float], count: int, spacing: float, noise_deg: float
) -> tuple[list[tuple[float, float]], list[float]]:
    """``count`` people on a ring around ``centre``, ``spacing`` m from their neighbours,
    facing its centre within ``noise_deg``."""
    radius = spacing / (2 * math.sin(math.pi / count))
    start = rng.uniform(0, 2 * math.pi)
    positions, headings = [], []
    for k in range(count):
        a = start + 2 * math.pi * k / count
        p = (centre[0] + radius * math.cos(a), centre[1] + radius * math.sin(a))
        positions.append(p)
        headings.append(_facing(p, centre) + math.radians(rng.gauss(0, noise_deg)))
    return positions, headings


def dense_room(rng: random.Random, frames: int = 40) -> list[Frame]:
    """Six groups of four to six people, each a ring 0.6 m between neighbours, the rings
    packed so that neighbouring groups' people stand about 0.6 m apart too (SALSA's
    spacing): the room is as dense as its groups."""
    out = []
    for _ in range(frames):
        positions: list[tuple[float, float]] = []
        headings: list[float] = []
        truth = []
        for g in range(6):
            count = rng.randint(4, 6)
            radius = 0.6 / (2 * math.sin(math.pi / count))
            centre = (2.0 + 1.9 * (g % 3), -1.0 + 1.9 * (g // 3))
            assert radius < 0.7  # rings 1.9 m apart: 0.5-0.8 m between neighbouring groups
            ring, faces = _ring(rng, centre, count, 0.6, 10.0)
            truth.append(frozenset(range(len(positions), len(positions) + count)))
            positions += ring
            headings += faces
        out.append(_frame(positions, headings, tuple(truth)))
    return out


def close_circle(rng: random.Random, frames: int = 40) -> list[Frame]:
    """Five or six people on a ring 0.8 m between neighbours, headings rounded to 45 or
    90 degrees (as datasets annotate them), and two loners 3 m or more away."""
    out = []
    for k in range(frames):
        count, step = (5 + k % 2), (math.pi / 4 if k % 4 < 2 else QUARTER)
        positions, headings = _ring(rng, (3.0, 0.0), count, 0.8, 10.0)
        headings = [round(h / step) * step for h in headings]
        positions += [(3.0, 3.5), (6.5, -3.0)]
        headings += [rng.randrange(4) * QUARTER for _ in range(2)]
        out.append(_frame(positions, headings, (frozenset(range(count)),)))
    return out


def side_by_side(rng: random.Random, frames: int = 40) -> list[Frame]:
    """Three or four pairs standing side by side 0.6 m apart, each pair facing the same
    way (a screen, a window, a queue), pairs 2 m or more apart: nobody in a group."""
    out = []
    for _ in range(frames):
        positions: list[tuple[float, float]] = []
        headings: list[float] = []
        for pair in range(rng.randint(3, 4)):
            way = rng.uniform(-math.pi, math.pi)
            at = (1.5 + 2.2 * pair, rng.uniform(-2.0, 2.0))
            side = (-math.sin(way) * 0.3, math.cos(way) * 0.3)
            for sign in (-1, 1):
                positions.append((at[0] + sign * side[0], at[1] + sign * side[1]))
                headings.append(way + math.radians(rng.gauss(0, 10.0)))
        out.append(_frame(positions, headings))
    return out


def scenes(seed: int = 51) -> dict[str, list[Frame]]:
    rng = random.Random(seed)
    return {
        "posters": posters(rng),
        "wide circle": wide_circle(rng),
        "loners": loners(rng),
        "dense room": dense_room(rng),
        "close circle": close_circle(rng),
        "side by side": side_by_side(rng),
    }
