"""The detector core alone: vectorized numpy vs a per-body pure-Python port of the tutorial.

The tutorial (ROS4HRI's HRIListener example) loops over bodies, builds each body's
transform, inverts it and tests ``acos(r.x / |r.xy|) < threshold``. ``tutorial_loop`` is
that loop in plain Python (quaternion -> rotation, r = -R^T t, per body), the baseline.
"""

from __future__ import annotations

import math
import time

import numpy as np

from facing_service.core.detector import classify


def tutorial_loop(translations: list[tuple], quaternions: list[tuple], threshold_deg: float):
    """Per body, as the tutorial does it: one transform inversion and one test each."""
    facing = []
    for (tx, ty, tz), (x, y, z, w) in zip(translations, quaternions, strict=True):
        # R^T t, written out from the rotation matrix of q
        rx = -((1 - 2 * (y * y + z * z)) * tx + 2 * (x * y + z * w) * ty + 2 * (x * z - y * w) * tz)
        ry = -(2 * (x * y - z * w) * tx + (1 - 2 * (x * x + z * z)) * ty + 2 * (y * z + x * w) * tz)
        norm = math.hypot(rx, ry)
        if norm < 1e-9:
            facing.append(False)
            continue
        angle = math.degrees(math.acos(max(-1.0, min(1.0, rx / norm))))
        facing.append(rx > 0 and angle < threshold_deg)
    return facing


def scene(n: int, seed: int = 155) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    t = rng.uniform(-5, 5, size=(n, 3))
    q = rng.normal(size=(n, 4))
    return t, q / np.linalg.norm(q, axis=1, keepdims=True)


def rate(fn, n: int, min_time: float = 0.2) -> float:
    """Bodies per second: repeat ``fn`` until ``min_time`` has passed; best of 3."""
    best = math.inf
    for _ in range(3):
        reps, started = 0, time.perf_counter()
        while True:
            fn()
            reps += 1
            elapsed = time.perf_counter() - started
            if elapsed >= min_time:
                break
        best = min(best, elapsed / reps)
    return n / best


def compare(n: int, min_time: float) -> dict:
    """Both implementations on the same scene of n bodies (checked to agree first)."""
    t, q = scene(n)
    t_list, q_list = list(map(tuple, t)), list(map(tuple, q))
    agree = tutorial_loop(t_list, q_list, 20.0) == classify(t, q, 20.0).facing.tolist()
    assert agree, "the two implementations disagree"
    vectorized = rate(lambda: classify(t, q, 20.0), n, min_time)
    loop = rate(lambda: tutorial_loop(t_list, q_list, 20.0), n, min_time)
    return {
        "n": n,
        "vectorized_per_s": vectorized,
        "loop_per_s": loop,
        "speedup": vectorized / loop,
    }


def measure(sizes: tuple[int, ...], min_time: float = 0.2) -> list[dict]:
    return [compare(n, min_time) for n in sizes]
