"""One annotated frame of an F-formation sequence (or a scene made like one): who, where,
facing which way, and the true groups. Its own module: the sequences' reader (``held_out``)
and the made scenes (``scenes``) both build them, and neither imports the other's
code for it."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np


@dataclass(frozen=True)
class Frame:
    ids: tuple[int, ...]
    positions: np.ndarray  # (N, 2) metres
    headings: np.ndarray  # (N,) radians
    truth: tuple[frozenset[int], ...]  # groups of two or more

    def wider(self, factor: float) -> Frame:
        return replace(self, positions=self.positions * factor)
