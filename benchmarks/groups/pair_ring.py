"""Whether two people could stand on one ring facing into it: what the remaining pair of
a group says by itself when its third member is out of sight.

A ring both stand on has its centre on the perpendicular bisector of the two; the pair
faces into it when each one's heading points near that centre. ``ring_error`` is the
least, over every such centre at a radius of 0.25 to 2 m, of the larger of the two
heading errors: 0 when both face one centre, 90° or more when no ring has them facing in
(one behind the other, facing the same way).
"""

from __future__ import annotations

import numpy as np

RADII_M = (0.25, 2.0)
OFFSETS_M = np.linspace(-3.0, 3.0, 601)  # along the bisector, every centimetre


def ring_error(members: np.ndarray, headings: np.ndarray) -> float:
    """Degrees: how far the better-facing ring both of ``members`` ((2, 2)) stand on is
    from what their ``headings`` say."""
    a, b = members
    middle, axis = (a + b) / 2, (b - a) / np.linalg.norm(b - a)
    centres = middle + OFFSETS_M[:, None] * np.array([-axis[1], axis[0]])  # (k, 2)
    radius = np.hypot(*(centres - a).T)
    to_centre = centres[:, None, :] - members[None, :, :]  # (k, 2, 2)
    off = np.arctan2(to_centre[..., 1], to_centre[..., 0]) - headings[None, :]
    worst = np.degrees(np.abs(np.angle(np.exp(1j * off)))).max(axis=1)
    inside = (radius >= RADII_M[0]) & (radius <= RADII_M[1])
    return float(worst[inside].min()) if inside.any() else 180.0
