"""Scripted people with ground truth, for the engagement benchmark: one person's track as
a noisy tracker reports it, each sample labelled engaging or not. Benchmark-only: the
simulator the service ships (``client.sim``) draws no labels."""

from __future__ import annotations

import math
import random
from dataclasses import dataclass

from facing_service.client.sim import POSITION_NOISE_M


@dataclass(frozen=True)
class Segment:
    """A scripted stretch of behaviour for ``labelled_track``: go from ``start`` to
    ``end`` (x, y in metres) in ``seconds``, looking ``yaw`` ('robot', 'away', 'path' or a
    heading in degrees); ``facing`` is the ground truth: is this person engaging? (None:
    no ground truth, e.g. while approaching, when both answers are defensible)."""

    seconds: float
    start: tuple[float, float]
    end: tuple[float, float]
    yaw: str | float
    facing: bool | None


@dataclass(frozen=True)
class LabelledSample:
    t: float
    x: float
    y: float
    yaw_deg: float
    facing: bool | None  # the ground truth of the segment


def labelled_track(
    segments: list[Segment],
    seed: int,
    rate_hz: float = 30.0,
    yaw_noise_deg: float = 5.0,
    dropout: float = 0.1,
    burst_every_s: float = 20.0,
) -> list[LabelledSample]:
    """One person's scripted track as a noisy tracker reports it: yaw and position
    jitter, ticks dropped at random (``dropout``) and in 0.5 s bursts (about one every
    ``burst_every_s``); dropped ticks are simply absent."""
    rng = random.Random(seed)
    samples = []
    t = 0.0
    burst_until = -1.0
    for segment in segments:
        ticks = max(1, round(segment.seconds * rate_hz))
        (x0, y0), (x1, y1) = segment.start, segment.end
        path = math.degrees(math.atan2(y1 - y0, x1 - x0)) if (x0, y0) != (x1, y1) else 0.0
        for i in range(ticks):
            t += 1.0 / rate_hz
            f = (i + 1) / ticks
            x, y = x0 + f * (x1 - x0), y0 + f * (y1 - y0)
            if rng.random() < 1.0 / (burst_every_s * rate_hz):
                burst_until = t + 0.5
            if t < burst_until or rng.random() < dropout:
                continue
            toward = math.degrees(math.atan2(-y, -x))
            yaw = (
                {"robot": toward, "away": toward + 180.0, "path": path}[segment.yaw]
                if isinstance(segment.yaw, str) else segment.yaw
            )  # fmt: skip
            samples.append(
                LabelledSample(
                    t,
                    x + rng.gauss(0, POSITION_NOISE_M),
                    y + rng.gauss(0, POSITION_NOISE_M),
                    float(yaw) + rng.gauss(0, yaw_noise_deg),
                    segment.facing,
                )
            )
    return samples
