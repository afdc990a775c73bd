"""A frame's social scene alone: what one computation costs with 20 people, the groups said
and where to join each (no slower than about 1.5 ms).

    python -m benchmarks.perf.scene [--people 20] [--rounds 200] [--repeat 5]

Twenty people in six groups of three or four around rings (the rest alone), moved a little
every computation so nothing is skipped as still; each computation followed by the scene's
snapshot (every group's join worked out). Printed: ms a computation, best of ``--repeat``
(this machine is shared: compare trees alternated, in one sitting).
"""

from __future__ import annotations

import argparse
import math
import random
import time

from facing_service.config.profiles import scene_params
from facing_service.config.settings import Settings
from facing_service.contract.poses import yaw_rotation
from facing_service.contract.stamps import Time
from facing_service.core.social.scene import FrameScene, Person

Standing = tuple[str, float, float, float]  # id, x, y, heading (degrees)


def crowd(people: int, seed: int = 1) -> list[Standing]:
    """Groups of three and four around rings of 0.8 m, each facing its centre; the rest
    alone, anywhere within 8 m."""
    rng = random.Random(seed)
    placed: list[Standing] = []
    while len(placed) < people and len(placed) < 20:
        cx, cy, n = rng.uniform(-6, 6), rng.uniform(-6, 6), 3 + len(placed) % 2
        for j in range(min(n, people - len(placed))):
            a = 2 * math.pi * j / (n + 1)
            placed.append((f"p{len(placed)}", cx + 0.8 * math.cos(a), cy + 0.8 * math.sin(a),
                           math.degrees(a) + 180))  # fmt: skip
    while len(placed) < people:
        placed.append((f"p{len(placed)}", rng.uniform(-8, 8), rng.uniform(-8, 8),
                       rng.uniform(0, 360)))  # fmt: skip
    return placed


def moved(standing: list[Standing], t: float) -> list[Person]:
    """Everyone a centimetre and a few degrees off, differently each time."""
    return [Person(i, (x + 0.01 * math.sin(t + k), y, 0.0), yaw_rotation(h + 3 * math.sin(t)))
            for k, (i, x, y, h) in enumerate(standing)]  # fmt: skip


def measure(people: int, rounds: int, repeat: int) -> list[float]:
    """ms a computation and its snapshot, each of ``repeat`` runs of ``rounds``."""
    scene, standing = FrameScene("f", scene_params(Settings())), crowd(people)
    for t in range(20):  # the groups said, their joins asked once
        scene.update(moved(standing, t), Time.of(1 + t), t * 0.1)
        scene.snapshot()
    runs = []
    for r in range(repeat):
        started = time.perf_counter()
        for k in range(rounds):
            t = 100 + r * rounds + k
            scene.update(moved(standing, t), Time.of(t), t * 0.1)
            scene.snapshot()
        runs.append((time.perf_counter() - started) / rounds * 1e3)
    return runs


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--people", type=int, default=20)
    parser.add_argument("--rounds", type=int, default=200)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    runs = measure(args.people, args.rounds, args.repeat)
    print(f"{args.people} people: {min(runs):.3f} ms a computation and its snapshot "
          f"(best of {args.repeat}; all {', '.join(f'{r:.3f}' for r in runs)})")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
