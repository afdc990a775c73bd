"""Groups that do not depend on what people are called: each frame of every
shared sequence grouped as listed, then with its people listed in another order and named
so that their ids sort the other way; the frames grouped otherwise, counted.

    python -m benchmarks.groups.order [--orders 3]

Frame by frame (``groups.detect`` with the shipped parameters, memory off) and through a
scene with the shipped memory (``scene.FrameScene``, each frame's people new to it: the
first look), as the live service lists people: sorted by id.

And how well the first look scores (F1 at T = 2/3, GCFF's way): as listed, and the mean
over the reorderings and renamings (where ties went by listing, the listing helped).

Beside them, how often each true group is listed consecutively in the data's own order
(and how often a random set of its size would be): where the annotators listed groups
together, a grouping whose ties go by listing order is helped by the answer.
"""

from __future__ import annotations

import argparse

import numpy as np

from facing_service.contract.poses import yaw_rotation
from facing_service.contract.stamps import Time
from facing_service.core.social.groups import GroupParams, detect, members
from facing_service.core.social.scene import FrameScene, Person

from .replay import shipped
from .scoring import f1
from .sequence_frame import Frame
from .sequences import SEQUENCES, load


def partition(ids: list[str], labels: np.ndarray) -> frozenset[frozenset[str]]:
    return frozenset(frozenset(ids[i] for i in m) for m in members(labels) if len(m) > 1)


def by_detect(ids: list[str], frame: Frame, order: np.ndarray) -> frozenset[frozenset[str]]:
    """The frame's groups with its people listed in ``order``."""
    labels = detect(frame.positions[order], frame.headings[order], GroupParams())
    return partition([ids[i] for i in order], labels)


def by_scene(ids: list[str], frame: Frame, order: np.ndarray) -> frozenset[frozenset[str]]:
    """The groups a scene with the shipped memory says of the frame, seen first (its
    people new), listed as the service lists them: by id."""
    scene = FrameScene("frame", shipped())
    people = [
        Person(ids[i], (float(frame.positions[i][0]), float(frame.positions[i][1]), 0.0),
               yaw_rotation(float(np.degrees(frame.headings[i]))))
        for i in order
    ]  # fmt: skip
    people.sort(key=lambda p: p.id)
    scene.update(people, Time.of(1), 0.0)
    said = scene.update(people, Time.of(2), 1.0)  # held past hold_s: said
    groups = scene.tracker.groups.values() if said is None else said.groups
    return frozenset(frozenset(g.members) - {""} for g in groups if len(g.members - {""}) > 1)


def changed(frames: list[Frame], how, orders: int, seed: int = 77) -> int:
    """Frames grouped otherwise in any of ``orders`` reorderings and renamings."""
    rng = np.random.default_rng(seed)
    count = 0
    for frame in frames:
        n = len(frame.ids)
        ids = [f"p{i:03d}" for i in frame.ids]
        base = how(ids, frame, np.arange(n))
        for _ in range(orders):
            order = rng.permutation(n)
            # named so that the ids sort the other way (a stable mapping of who is who)
            renamed = {a: f"q{999 - k:03d}" for k, a in enumerate(sorted(ids))}
            other = how([renamed[i] for i in ids], frame, order)
            back = {v: k for k, v in renamed.items()}
            if frozenset(frozenset(back[m] for m in g) for g in other) != base:
                count += 1
                break
    return count


def first_look_f1(frames: list[Frame], orders: int, seed: int = 77) -> tuple[float, float]:
    """The first look's F1 (T = 2/3): the data's listing and ids, and the mean over
    ``orders`` other listings, ids renamed to sort the other way."""
    rng = np.random.default_rng(seed)
    runs: list[list[list[frozenset[int]]]] = [[] for _ in range(orders + 1)]
    for frame in frames:
        n = len(frame.ids)
        for k in range(orders + 1):
            order = np.arange(n) if k == 0 else rng.permutation(n)
            name = (lambda i: f"p{i:03d}") if k == 0 else (lambda i: f"q{999 - i:03d}")
            said = by_scene([name(i) for i in frame.ids], frame, order)
            back = {name(i): i for i in frame.ids}
            runs[k].append([frozenset(back[m] for m in g) for g in said])
    figures = [f1(frames, found, 2 / 3) for found in runs]
    return figures[0], float(np.mean(figures[1:]))


def listed_together(frames: list[Frame], seed: int = 77) -> tuple[float, float]:
    """The share of true groups whose members are listed consecutively, and the share
    random sets of the same sizes would have."""
    rng = np.random.default_rng(seed)
    together = chance = total = 0
    for frame in frames:
        where = {person: k for k, person in enumerate(frame.ids)}
        for group in frame.truth:
            if not all(person in where for person in group):
                continue
            spots = sorted(where[person] for person in group)
            drawn = sorted(rng.choice(len(frame.ids), len(group), replace=False))
            total += 1
            together += spots[-1] - spots[0] == len(spots) - 1
            chance += drawn[-1] - drawn[0] == len(drawn) - 1
    return together / max(total, 1), chance / max(total, 1)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--orders", type=int, default=3)
    args = parser.parse_args(argv)
    print(f"{'sequence':22} frames  frame by frame  first look (memory)  groups listed together"
          "  first look F1: listed, reordered")  # fmt: skip
    for name in SEQUENCES:
        frames = load(name)
        d = changed(frames, by_detect, args.orders)
        s = changed(frames, by_scene, args.orders)
        together, chance = listed_together(frames)
        listed, reordered = first_look_f1(frames, args.orders)
        print(f"{name:22} {len(frames):6}  {d:14}  {s:19}  {together:7.0%} (chance {chance:.0%})"
              f"  {listed:.3f}, {reordered:.3f}", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
